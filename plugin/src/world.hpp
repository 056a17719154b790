// One Earshot world behind the C API: the control side (what the host set),
// the hand-off to the audio thread, and the audio side (esRender).
//
// Hand-off: the control thread keeps the whole world state in `control_`
// and publishes a copy into a triple buffer (three preallocated snapshots):
// in immediate mode after every change, in deferred mode on esCommit. The
// audio thread, at the start of each block, takes the newest published
// snapshot if there is one (an atomic exchange of indices: no lock, no
// wait, no allocation), so everything in one snapshot is heard from the
// same block. Play/stop/rewind are state plus a serial number, so they
// survive the hand-off as state does.
//
// HRTF switch (esWorldHrtf): the control thread prepares a renderer for the
// new set and hands it over through an atomic pointer; the audio thread
// adopts it at a block start (audio::CrossfadeSwitch, the project's one HRTF
// switch: the old and the new side by side on the same input for a warm-up,
// then a crossfade), and hands the old one back through another atomic
// pointer for the control thread to free. No lock, no allocation on the
// audio thread.
//
// Ambisonic beds (ABI 1.5): a source whose buffer or callback holds an
// Ambisonic field plays it as a bed: one BedRenderer per bed (bed_voice.hpp,
// made on the control thread with the decoder of the world's set and order,
// from the process's DecoderCache, and handed over like a renderer), turned
// by the same composed head the point sources hear, its gain ramped, mixed
// into the renderer's mix before the limiter.
//
// The Ambisonic tier (ES_QUALITY): a renderer made with an AmbisonicBus
// (audio/renderer.hpp, ambisonics/ambisonic_bus.hpp), prepared on the
// control thread and handed over through the same switch as a new HRTF set.
// Decoders are designed only when a bed or the tier needs one.
//
// Buffers: the samples are owned by the control side. A deleted buffer's
// samples are freed only when none of the three snapshots refers to them,
// so the audio thread never reads freed memory.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bed_voice.hpp"
#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/crossfade_switch.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/audio/room_reverb.hpp"
#include "earshot/earshot.h"
#include "earshot/geometry.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/head/tracked_head.hpp"
#include "earshot/pose_slot.hpp"

namespace earshot::plugin {

/// A failed call: the code and, for people, why.
struct Failure {
  ESenum code;
  std::string message;
};

/// A source as the host set it; trivially copyable, so snapshots copy cheaply.
struct SourceParams {
  ESsource handle = 0;  ///< 0: the slot is free
  audio::SourceState state{};
  Vec3 velocity{0, 0, 0};
  double pitch = 1.0;
  bool looping = false;
  ESbuffer buffer = 0;
  const float* data = nullptr;  ///< the buffer's samples (owned by the control side)
  std::size_t frames = 0;
  double rate_ratio = 1.0;  ///< buffer rate / world rate
  ESsourcecallback callback = nullptr;
  void* user = nullptr;
  int order = 0;  ///< > 0: an Ambisonic field of this order (buffer or field callback), not a point
  Quat orientation{1, 0, 0, 0};  ///< a field's orientation in the world (or the head, when relative)
  ESambisoniccallback field_callback = nullptr;
  ESenum play_state = ES_INITIAL;  ///< requested: initial, playing, paused, stopped
  std::uint64_t play_serial = 0;   ///< bumped by every play / stop / rewind
};

struct Snapshot {
  HeadPose listener{};  ///< position and orientation (the rest unused)
  double listener_gain = 1.0;
  Vec3 listener_velocity{0, 0, 0};
  Vec3 head_position{0, 0, 0};       ///< esSetHeadPose (no tracker)
  Quat head_orientation{1, 0, 0, 0};
  double doppler_factor = 1.0;
  double speed_of_sound = 343.3;
  bool reverb_enabled = false;
  audio::RoomParams room{};
  std::uint64_t room_serial = 0;
  std::vector<SourceParams> sources;  ///< max_sources entries, sized once
};

class World {
 public:
  /// Throws Failure (ES_HRTF_ERROR, ES_INVALID_VALUE).
  explicit World(const ESworldparams& p);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // ---- control thread ----
  [[nodiscard]] bool on_control_thread() const { return control_thread_.load() == std::this_thread::get_id(); }
  void set_control_thread() { control_thread_.store(std::this_thread::get_id()); }
  void set_error(std::string m) { error_ = std::move(m); }
  [[nodiscard]] const char* error() const { return error_.c_str(); }

  void set_commit_mode(bool deferred) { deferred_ = deferred; }
  [[nodiscard]] bool deferred() const { return deferred_; }
  void changed() { if (!deferred_) publish(); }  ///< after every change
  void commit() { publish(); }

  [[nodiscard]] Snapshot& state() { return control_; }
  [[nodiscard]] const ESworldparams& params() const { return params_; }
  [[nodiscard]] std::uint64_t blocks_rendered() const { return blocks_.load(std::memory_order_relaxed); }

  /// The slot of a live source handle, or nullopt.
  [[nodiscard]] std::optional<std::size_t> source_slot(ESsource s) const;
  [[nodiscard]] ESsource create_source();  ///< 0 when all slots are in use
  void delete_source(std::size_t slot);
  /// What the host would see: the requested state, or the audio side's once it caught up.
  [[nodiscard]] ESenum source_state(std::size_t slot) const;
  [[nodiscard]] double source_offset(std::size_t slot) const;

  struct BufferInfo {
    const float* data;  ///< mono, or an Ambisonic buffer's channels planar (ambiX)
    std::size_t frames;
    double rate_ratio;
    int order;  ///< 0: mono
  };
  [[nodiscard]] std::optional<BufferInfo> buffer(ESbuffer b) const;
  [[nodiscard]] ESbuffer create_buffer(const float* samples, std::size_t frames, double rate);  ///< 0: full
  /// An Ambisonic buffer: `planar` holds (order+1)^2 channels one after the other, ambiX. 0: full.
  [[nodiscard]] ESbuffer create_ambisonic_buffer(std::vector<float> planar, double rate, int order);
  /// False while a source has it set.
  bool delete_buffer(ESbuffer b);

  /// Switches to the SOFA set at `path` (nullptr: MIT KEMAR) while playing;
  /// prepares it here (the process's HRTF cache). Throws Failure (ES_HRTF_ERROR).
  void set_hrtf(const char* path);
  /// Frames both sets render before the crossfade, and its length.
  static constexpr std::size_t kWarmFrames = audio::CrossfadeSwitch<audio::Renderer>::kWarm,
                               kFadeFrames = audio::CrossfadeSwitch<audio::Renderer>::kFade;

  /// Makes slot `slot` ready to play a field of `order` (0: a point source):
  /// a bed renderer with the decoder of the world's set for that order
  /// (designed or read from the caches here). Throws Failure (ES_INVALID_VALUE).
  void prepare_bed(std::size_t slot, int order);
  /// The renderer tier: 0 direct, N > 0 `ambisonic:N` (a renderer prepared
  /// here and faded in at a block start). Throws Failure.
  void set_quality(int order);
  [[nodiscard]] int quality() const { return quality_; }
  /// The decoder design of beds and of the tier made from now on.
  void set_decoder_method(ambisonics::DecoderMethod m) { design_.method = m; }
  [[nodiscard]] ambisonics::DecoderMethod decoder_method() const { return design_.method; }

  void attach_tracker(const char* spec);  ///< throws Failure
  /// With options (esAttachTrackerEx: where to send the poses); throws Failure.
  void attach_tracker(const char* spec, const tracker::TrackerOptions& options);
  void recenter();
  /// The tracker's status for the host (locks the tracker's status mutex,
  /// shared with the tracker thread only). Writes all of `out` but its size.
  void tracker_state(EStrackerstate& out) const;
  /// The tracker's picture (locks the source's picture mutex, shared with
  /// the tracker thread only). Writes all of `out` but its size.
  void tracker_image(EStrackerimage& out) const;
  [[nodiscard]] bool propagation_delay() const { return params_.propagation_delay != ES_FALSE; }

  // ---- any thread ----
  [[nodiscard]] HeadPose head_pose() const { return used_pose_.load(); }

  /// Head prediction (on by default): each block turns the head to where the
  /// tracker's pose, carried on at the filter's velocities, will be when the
  /// block is heard: now + one block + `host_latency_s` (the host's own
  /// output latency, 0 when it does not say), at most
  /// kMaxHeadPredictionS ahead of the pose (head_pose.hpp). Any thread.
  void set_head_prediction(bool on, double host_latency_s) {
    host_latency_s_.store(std::isfinite(host_latency_s) ? std::max(0.0, host_latency_s) : 0.0, std::memory_order_relaxed);
    predict_head_.store(on, std::memory_order_relaxed);
  }
  [[nodiscard]] bool head_prediction() const { return predict_head_.load(std::memory_order_relaxed); }
  [[nodiscard]] double host_latency_s() const { return host_latency_s_.load(std::memory_order_relaxed); }
  /// Seconds from a block's start to when it is heard (what the prediction adds to now).
  [[nodiscard]] double output_latency_s() const {
    return static_cast<double>(params_.block_size) / static_cast<double>(params_.sample_rate) +
           host_latency_s_.load(std::memory_order_relaxed);
  }

  // ---- audio thread ----
  /// False when another render is running.
  [[nodiscard]] bool begin_render() {
    if (rendering_.exchange(true, std::memory_order_acquire)) return false;
    render_thread_.store(std::this_thread::get_id(), std::memory_order_relaxed);
    return true;
  }
  void end_render() {
    render_thread_.store(std::thread::id{}, std::memory_order_relaxed);
    rendering_.store(false, std::memory_order_release);
  }
  /// True inside esRender on this thread (e.g. in a source callback).
  [[nodiscard]] bool rendering_here() const {
    return render_thread_.load(std::memory_order_relaxed) == std::this_thread::get_id();
  }
  void render(float* left, float* right);

  /// A source's playback on the audio side.
  struct Playback {
    ESsource handle = 0;
    std::uint64_t serial = 0;
    ESenum state = ES_INITIAL;
    double position = 0.0;  ///< in buffer frames
  };

 private:
  struct Buffer {
    std::uint16_t generation = 1;
    bool alive = false;
    std::vector<float> samples;
    double rate = 0.0;
    int order = 0;  // > 0: Ambisonic, samples planar
  };

  void publish();
  void reclaim_buffers();
  void reclaim_renderers();  // control side: frees what the audio side handed back
  void adopt_new_renderer();  // audio side, at a block start
  void feed(std::size_t slot, const SourceParams& sp, std::span<float> in, double doppler_shift);
  /// A bed's block: playback (or its callback) into its unit, turned and
  /// decoded, gain-ramped into the renderers' mixes before the limiter.
  void render_bed(std::size_t slot, const SourceParams& sp, const Snapshot& s, const Quat& listener,
                  audio::Renderer& renderer, audio::Renderer* fading);
  /// Playback of a field's buffer or callback into `planar` (channels x block).
  void feed_field(std::size_t slot, const SourceParams& sp, std::span<float> planar);
  [[nodiscard]] std::unique_ptr<audio::Renderer> make_renderer() const;  // control side: the set and tier in use
  [[nodiscard]] std::shared_ptr<const ambisonics::DecoderFilters> decoder(int order) const;
  [[nodiscard]] double doppler_shift(const SourceParams& sp, const Snapshot& s) const;

  ESworldparams params_;
  std::atomic<std::thread::id> control_thread_;
  std::string error_;
  bool deferred_ = false;

  // control side
  Snapshot control_;
  std::string hrtf_path_;        // the SOFA file in use ("" : the default set)
  audio::PreparedHrtf hrtf_;     // its prepared data (shared with the renderers)
  int quality_ = 0;              // 0 direct, N ambisonic:N
  ambisonics::DecoderDesign design_;
  std::vector<std::uint16_t> source_generation_;
  std::vector<Buffer> buffers_;

  // the triple buffer
  std::array<Snapshot, 3> snaps_;
  static constexpr unsigned kFresh = 4u;
  std::atomic<unsigned> middle_{1};
  unsigned back_ = 0;   // the control thread's
  unsigned front_ = 2;  // the audio thread's

  // audio side
  std::atomic<bool> rendering_{false};
  std::atomic<std::thread::id> render_thread_{};
  std::atomic<std::uint64_t> blocks_{0};
  audio::RendererConfig renderer_config_;
  audio::CrossfadeSwitch<audio::Renderer> renderers_;  // the set in use, and the one fading out
  std::unique_ptr<audio::RoomReverb> room_;
  // The HRTF switch (see the top): owned while in these slots.
  std::atomic<audio::Renderer*> incoming_{nullptr};  // control -> audio
  std::atomic<audio::Renderer*> outgoing_{nullptr};  // audio -> control, to free
  std::unique_ptr<audio::Renderer> retired_;         // audio side: faded out, outgoing_ was full
  std::vector<float> fade_l_, fade_r_;
  std::uint64_t room_serial_seen_ = 0;
  bool reverb_was_on_ = false;
  std::size_t voices_ = 0;  // renderer voices added so far
  std::vector<Playback> playback_;
  std::vector<std::unique_ptr<BedVoice>> bed_voices_;  // one per slot, made at construction
  std::vector<double> bed_gain_;                        // audio side: each bed's last gain (< 0: none yet)
  std::unique_ptr<std::atomic<std::uint64_t>[]> status_;   // serial << 8 | state index
  std::unique_ptr<std::atomic<double>[]> offsets_;
  head::HeadReader head_reader_;  // audio side

  // tracking
  PoseSlot tracker_slot_;  // outlives every tracker attached (the audio side reads it)
  std::atomic<bool> tracker_on_{false};
  std::atomic<bool> predict_head_{true};
  std::atomic<double> host_latency_s_{0.0};
  std::unique_ptr<head::TrackedHead> tracker_;
  PoseSlot used_pose_;  // written by the audio thread, read anywhere
};

}  // namespace earshot::plugin
