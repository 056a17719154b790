// The block renderer: sources around one listener, to a stereo (binaural)
// block. Per source and block, with the listener's pose read once:
//   direction and distance relative to the head -> HRTF interpolation (three
//   measurements, their weights, the ITD; for a source nearer than the set's
//   measurement distance, each ear from its own direction and with the
//   near-field level of near_field.hpp) -> per-ear fractional delay (ITD +
//   propagation delay: a moving source's changing delay is its Doppler
//   shift) -> each ear panned, with the distance gain, into the three
//   measured directions' convolvers of a DirectionBank, the weights ramping
//   across the block when the source or the head moves (a per-sample
//   crossfade of the blended filter). Air absorption (a distance-dependent
//   high shelf) filters the source first. The bank then convolves each
//   direction in use once for every source in it.
// Each source also feeds a mono reverb send bus (the reverb is separate).
// The mix goes through the master gain and a peak limiter, so the output
// never exceeds full scale and never holds NaN or infinity.
//
// The Ambisonic tier: a renderer made with a SourceBus (source_bus.hpp)
// renders every source up to its HRTF as above (distance gain, cone, air
// absorption, propagation delay and Doppler, one delay read instead of one
// per ear) and hands it to the bus, which encodes it into an order-N
// Ambisonic bus and decodes that once per block; no direction bank, no
// near field (the decoder's filters carry the ITD). The mix, the reverb
// send and the limiter are the same.
//
// Threads: configure sources and the listener from one control thread
// between render() calls (the plugin adds the lock-free hand-off); render()
// itself never allocates, locks, logs or does I/O.
//
// Frames: OpenAL's world frame (+x right, +y up, -z ahead), metres, seconds.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/air_absorption.hpp"
#include "earshot/audio/cone.hpp"
#include "earshot/audio/direction_bank.hpp"
#include "earshot/audio/distance_model.hpp"
#include "earshot/audio/fractional_delay.hpp"
#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/audio/near_field.hpp"
#include "earshot/audio/source_bus.hpp"
#include "earshot/geometry.hpp"
#include "earshot/head_pose.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::audio {

// Points and orientations are earshot::Vec3 and earshot::Quat (earshot/geometry.hpp).

struct RendererConfig {
  double sample_rate = 48000.0;
  std::size_t block = 128;
  std::size_t max_sources = 64;
  double max_distance_m = 100.0;   ///< longest propagation delay kept
  double speed_of_sound = 343.3;   ///< m/s, OpenAL's default
  double doppler_factor = 1.0;     ///< 0: no propagation delay, no Doppler
  double master_gain = 1.0;
  /// Sources nearer than the set's measurement distance get parallax and
  /// the near-field level (near_field.hpp); off: every source is rendered
  /// from the farthest shell as if in its far field (the distance model
  /// alone sets its level).
  bool near_field = true;
};

struct SourceState {
  Vec3 position{0, 0, -1};
  double gain = 1.0;
  double min_gain = 0.0;  ///< after distance and cone attenuation (OpenAL's AL_MIN_GAIN)
  double max_gain = 1.0;  ///< likewise (AL_MAX_GAIN)
  DistanceParams distance{};
  ConeParams cone{};
  double reverb_send = 0.0;  ///< linear gain into the reverb bus
  double air_absorption = 0.0;  ///< OpenAL's air absorption factor (0..10)
  bool relative = false;     ///< position relative to the listener
};

/// Direction and distance of a world point as the listener hears it:
/// SOFA azimuth (counter-clockwise from ahead, radians), elevation, metres.
struct HeadRelative {
  double azimuth = 0.0, elevation = 0.0, distance = 0.0;
};
[[nodiscard]] HeadRelative head_relative(const Vec3& point, const HeadPose& listener);

class Renderer {
 public:
  struct HeadFrame;  ///< a point as the head sees it (renderer.cpp)
  /// Prepares the set's spectra for cfg.block itself.
  Renderer(std::shared_ptr<const hrtf::HrtfSet> hrtf, RendererConfig cfg);
  /// Uses prepared data (e.g. from HrtfCache), shared with other renderers:
  /// its spectra must be for cfg.block.
  Renderer(const PreparedHrtf& hrtf, RendererConfig cfg);
  /// The Ambisonic tier: every source goes into `bus` (which must take
  /// cfg.max_sources voices) instead of the direction bank.
  Renderer(const PreparedHrtf& hrtf, RendererConfig cfg, std::unique_ptr<SourceBus> bus);
  ~Renderer();

  /// Adds a source; returns its index, or -1 when max_sources are in use.
  int add_source(const SourceState& s);
  void set_source(int index, const SourceState& s);
  /// The listener's head in the world (position, orientation; the rest of
  /// the pose is not used) and its gain (OpenAL's AL_GAIN on the listener).
  void set_listener(const HeadPose& pose, double gain = 1.0) {
    listener_ = pose;
    listener_gain_ = gain;
  }

  /// The mono input block of a source: write block() samples before render().
  [[nodiscard]] std::span<float> source_input(int index);

  /// Renders one block into left and right (block() samples each).
  void render(std::span<float> left, std::span<float> right);

  /// The reverb send of the last block (mono, block() samples).
  [[nodiscard]] std::span<const float> reverb_send() const { return send_; }
  /// Adds a stereo signal (e.g. the reverb's return) into the next render's mix.
  [[nodiscard]] std::span<float> return_left() { return ret_l_; }
  [[nodiscard]] std::span<float> return_right() { return ret_r_; }

  [[nodiscard]] std::size_t block() const { return cfg_.block; }
  [[nodiscard]] const RendererConfig& config() const { return cfg_; }
  /// Convolutions (measured direction x ear) the last render() ran: what
  /// the sources' filter blends cost (benchmarks report it per source).
  [[nodiscard]] std::size_t convolutions() const { return bank_ ? bank_->lanes_run() : 0; }
  /// The Ambisonic tier's bus, or null for the direct renderer.
  [[nodiscard]] const SourceBus* bus() const { return bus_.get(); }

 private:
  struct Voice;
  // The steps of render(), per source (renderer.cpp).
  void prefetch_after(std::size_t s) const;  // the next sources' state and lanes, on their way to the cache
  void render_source(Voice& v, const HeadPose& listener, double listener_gain);
  void render_to_bus(std::size_t index, Voice& v, const HeadPose& listener, double listener_gain);  // the tier
  [[nodiscard]] double source_gain(const Voice& v, const HeadFrame& hr, const HeadPose& frame, double listener_gain) const;
  void add_send(const Voice& v, double g0, double g);
  void aim_far(Voice& v, const HeadFrame& hr);   // the blend of measurements towards the source
  void aim_near(Voice& v, const HeadFrame& hr);  // each ear's own blend and the near ITD (parallax)
  [[nodiscard]] double propagation_delay(Voice& v, const HeadFrame& hr, const HeadPose& frame) const;  // samples
  void near_field_level(Voice& v, const HeadFrame& hr);  // each ear's rigid-sphere level filter
  void pan(Voice& v, const hrtf::Interpolation& left, const hrtf::Interpolation& right, double gain);
  void limit(std::span<float> left, std::span<float> right);  // master gain, peak limiter, clamp

  std::shared_ptr<const hrtf::HrtfSet> hrtf_;
  RendererConfig cfg_;
  HeadPose listener_;
  double listener_gain_ = 1.0;
  std::vector<std::unique_ptr<Voice>> voices_;
  std::size_t active_ = 0;
  std::shared_ptr<const NearFieldTable> near_field_;  // shared by every renderer at this rate and set; null when off
  std::unique_ptr<DirectionBank> bank_;  // the measured directions' convolvers, shared by every voice; null in the tier
  std::unique_ptr<SourceBus> bus_;       // the Ambisonic tier's bus, or null
  std::vector<float> send_, ret_l_, ret_r_, mix_l_, mix_r_;
  double limiter_gain_ = 1.0;
};

}  // namespace earshot::audio
