// One mono signal placed around a listener's head: the LV2 plugin's DSP,
// kept free of LV2 so tests drive it alone.
//
// A DSP unit in the Resonance way: constructed with the sample rate and the
// HRTF data prepared for its block (audio/hrtf_cache.hpp), it allocates
// everything then; update() takes new parameters, process() runs on the
// audio thread for any number of frames and never allocates, locks or does
// I/O. Inside, the renderer (audio/renderer.hpp) works in fixed blocks of
// block() frames; process() buffers through a FIFO, so the output is the
// rendered input exactly block() frames later (latency(), what the plugin
// reports on its latency port), whatever frame counts the host passes.
//
// Frames and units: OpenAL's world frame (+x right, +y up, -z ahead).
// Azimuth in degrees, counter-clockwise seen from above (positive to the
// left: the SOFA / AES69 and Ambisonics convention), elevation positive up,
// distance in metres from the centre of the head.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "earshot/audio/distance_model.hpp"
#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/audio/room_reverb.hpp"
#include "earshot/geometry.hpp"

namespace earshot::lv2 {

struct PannerParams {
  double azimuth_deg = 0.0;    ///< positive to the left
  double elevation_deg = 0.0;  ///< positive up
  double distance_m = 1.0;
  double gain_db = 0.0;
  audio::DistanceModel distance_model = audio::DistanceModel::inverse_clamped;
  /// 0: no room; i > 0: audio::room_presets()[i - 1].
  int room = 0;
  double reverb_send_db = -12.0;  ///< <= kReverbOffDb: nothing into the room
  Quat head_orientation{1, 0, 0, 0};  ///< the listener's head in the world
  Vec3 head_position{0, 0, 0};        ///< metres
};

/// At or below this send level the room gets nothing.
inline constexpr double kReverbOffDb = -60.0;

/// Where a source at (azimuth, elevation, distance) sits in the world frame.
[[nodiscard]] Vec3 position_of(double azimuth_deg, double elevation_deg, double distance_m);

class BinauralPanner {
 public:
  /// The renderer's block; also the latency in frames.
  static constexpr std::size_t kBlock = 128;

  /// `hrtf` must be prepared for kBlock at `sample_rate`. Allocates all.
  BinauralPanner(const audio::PreparedHrtf& hrtf, double sample_rate, std::string hrtf_path = {});
  ~BinauralPanner();
  BinauralPanner(const BinauralPanner&) = delete;
  BinauralPanner& operator=(const BinauralPanner&) = delete;

  /// New parameters; heard from the next internal block. Never allocates.
  void update(const PannerParams& p);
  /// `frames` samples of `in` to `left` and `right`, delayed by latency().
  /// `in` may alias either output. Never allocates, locks or does I/O.
  void process(const float* in, float* left, float* right, std::size_t frames);
  /// Silence in the FIFO and the room's tail (after a transport jump).
  void reset();

  [[nodiscard]] std::size_t latency() const { return kBlock; }
  [[nodiscard]] double sample_rate() const { return rate_; }
  /// The SOFA file this panner renders with ("" for the default set).
  [[nodiscard]] const std::string& hrtf_path() const { return hrtf_path_; }

 private:
  void render_block();

  double rate_;
  std::string hrtf_path_;
  audio::PreparedHrtf hrtf_;
  audio::Renderer renderer_;
  audio::RoomReverb room_;
  int source_ = -1;
  int room_index_ = 0;
  std::vector<float> in_, out_l_, out_r_;  // the FIFO, kBlock each
  std::size_t fill_ = 0;
};

}  // namespace earshot::lv2
