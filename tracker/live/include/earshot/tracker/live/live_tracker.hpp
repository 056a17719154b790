// The tracker thread: reads a FrameSource, runs the live pipeline
// (live_pipeline.hpp) and publishes every pose into a PoseSlot, the only
// link to the audio side. Starts in the constructor, stops in the destructor
// (std::jthread: stop requested, then joined); a source that ends or fails
// stops the thread by itself and says why in status() (or, with
// LiveConfig::keep_running_after_end, the thread goes on publishing the lost
// pose, held then eased to neutral, until stopped).
//
// status() is for the control side (a UI, a status line): a copy made under
// a mutex shared with the tracker thread only, never with the audio side;
// so is thumbnail() (a camera source's newest frame, small, with its dots).
//
// Every published pose is also offered to the senders LiveConfig::send names
// (tracker/send: non-blocking, rate-capped); senders() reports what they did.
//
// The source's own camera and beacon model (FrameSource::camera(), model():
// a webcam's resolution and focal length, a tag's corners) replace the
// configured ones, at the start and whenever the source (re)connects.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "earshot/pose_slot.hpp"
#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/send/pose_sender.hpp"

namespace earshot::tracker {

class LiveTracker {
 public:
  /// Called on the tracker thread after each publication (recording, UIs).
  /// Keep it short: the next frame waits for it.
  using PoseCallback = std::function<void(const HeadPose&)>;

  /// One tracker frame (a camera frame, or a pose from a source that solves
  /// its own), for recordings: what the pipeline put out for it, with the
  /// tracker's state, and for camera frames the beacon's absolute pose in
  /// the camera frame (mm), once the tracker has one. Notes carry no frame
  /// and make no row.
  struct FrameRow {
    HeadPose listener;
    std::optional<Pose> camera;
  };
  using FrameCallback = std::function<void(const FrameRow&)>;

  /// What the source said about its device, from its notes.
  enum class Link {
    unknown,       ///< nothing said yet (simulator, replay, UDP: no device to find)
    searching,     ///< no device found yet; still looking (see note)
    connected,     ///< the device answered and was set up
    disconnected,  ///< the device went away; reconnecting
  };

  /// One dot of the newest camera frame, in camera pixels (+x right, +y down).
  struct Dot {
    double x = 0, y = 0;
    int size = -1;   ///< as the camera reports it (Wii: 0..15); -1 unknown
    int label = -1;  ///< LED 0..3 the pipeline assigned; -1 unlabelled
  };

  struct Status {
    PoseState state = PoseState::searching;
    bool running = true;
    bool ended = false;  ///< the source ended (replay done) or failed (see error)
    Link link = Link::unknown;
    std::uint64_t frames = 0, published = 0, dropped = 0, rejected_dots = 0;
    double rate_hz = 0.0;  ///< camera frames or direct poses over the last second (wall clock)
    bool camera = false;   ///< the source delivers camera frames (dots below), not poses
    std::array<std::optional<Dot>, kSlots> dots;  ///< newest frame, by camera slot; none when stale
    std::string source;  ///< the source's describe()
    std::string note;    ///< the last note from the source (connected, disconnected...)
    std::string error;   ///< why the thread stopped, when a source failed
  };

  /// Throws what opening a sender throws (a host that does not resolve)
  /// before the thread starts.
  LiveTracker(std::unique_ptr<FrameSource> source, PoseSlot& slot, LiveConfig cfg = {},
              PoseCallback on_pose = {}, FrameCallback on_frame = {});
  ~LiveTracker();  ///< stops and joins
  LiveTracker(const LiveTracker&) = delete;
  LiveTracker& operator=(const LiveTracker&) = delete;

  /// The next pose becomes neutral (any thread).
  void recenter() { recenter_.store(true, std::memory_order_relaxed); }
  /// Asks the thread to stop and waits for it (idempotent).
  void stop();
  [[nodiscard]] bool running() const { return running_.load(std::memory_order_acquire); }
  [[nodiscard]] Status status() const;
  /// The source's newest frame, thumbnail-sized (false: it has none).
  bool thumbnail(Thumbnail& out) const { return source_->thumbnail(out); }
  /// Where the poses go (LiveConfig::send); their counters may be read any time.
  [[nodiscard]] const PoseSenders& senders() const { return senders_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Loop;
  void run(std::stop_token stop);
  // The steps of run.
  /// One event from the source; false when the source ended.
  bool handle(Loop& l, const SourceEvent& e);
  void note_link(Loop& l, const SourceNote& n);
  void show_dots(Loop& l, const CameraFrame& frame, Clock::time_point wall);
  void process(const SourceEvent& e, double now);
  void update_status(Loop& l, Clock::time_point wall);

  std::unique_ptr<FrameSource> source_;
  PoseSlot& slot_;
  bool keep_running_after_end_;
  LivePipeline pipeline_;
  PoseCallback on_pose_;
  FrameCallback on_frame_;
  PoseSenders senders_;
  std::atomic<bool> recenter_{false};
  std::atomic<bool> running_{true};
  mutable std::mutex status_mutex_;  // guards status_ (never touched by the audio side)
  Status status_;
  std::jthread thread_;  // last: starts after everything above exists
};

}  // namespace earshot::tracker
