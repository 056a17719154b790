// The live tracker's per-event work, without the thread: source event in,
// listener pose out. Pure and deterministic (time comes with the event), so
// tests drive it frame by frame and the thread (live_tracker.hpp) stays thin.
//
//   camera frame -> drop impossible dots (NaN, outside the image)
//                -> DotTracker (label -> solve -> filter, tracking/predicted/lost),
//                   or for labelled frames (a tag's corners) LabelledTracker
//                   (solve -> filter, the same states)
//                -> level the camera with gravity (accelerometer, while still)
//                -> relative to the pose captured at recenter
//                -> audio world frame (OpenAL: +x right, +y up, -z ahead)
//   direct pose  -> relative to the recenter pose (already in audio axes)
//
// Each pose carries the eskf's angular and linear velocity (audio axes) and
// the steady-clock time it was computed, so the audio side can carry it on
// to the time its block is heard (earshot::extrapolate, head_pose.hpp).
//
// States: searching (no pose since start), tracking, predicted (a short gap
// bridged by the DotTracker), lost. When tracking is lost the listener pose
// holds for `hold_s`, then eases to neutral (origin, looking ahead) over
// `ease_s`; when tracking resumes it blends back in over `resume_s`. Nothing
// jumps, and nothing non-finite comes out.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "earshot/head_pose.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/send/send_spec.hpp"
#include "earshot/tracker/track/labelled_tracker.hpp"

namespace earshot::tracker {

struct LiveConfig {
  Camera camera = Camera::with_focal(1280.0);
  LedModel model = LedModel::thesis();
  /// eskf: never worse than the raw solve on any motion profile, beacon or
  /// pixel mode of tests/bench/tracker_motion (One Euro was, on good beacons).
  TrackerConfig tracker{.filter = FilterKind::eskf};
  double hold_s = 0.5;     ///< lost: hold the last pose this long
  double ease_s = 1.5;     ///< then ease to neutral over this long
  double resume_s = 0.15;  ///< blend back to tracking over this long
  /// Direct pose sources (OSC, opentrack) may send only on change: their
  /// last pose counts as current this long before the state turns lost.
  double direct_timeout_s = 2.0;
  std::uint16_t recenter_buttons = 0x0800 | 0x8000;  ///< wiimote::Buttons::a | home
  bool level_from_accel = true;
  /// LiveTracker: when the source ends or fails, keep the thread publishing
  /// the lost pose (hold, then ease to neutral) until it is stopped, instead
  /// of stopping with the pose where it was (a host that plays on wants this).
  bool keep_running_after_end = false;
  int still_frames = 30;        ///< accelerometer steady this many frames = still
  double still_tolerance_g = 0.02;
  /// LiveTracker: send every pose it publishes on to these (tracker/send:
  /// OSC or opentrack over UDP, each at most at its rate); empty: nowhere.
  std::vector<SendSpec> send;
};

/// `cfg` with the camera and beacon model of `source` where it defines them
/// (a webcam's resolution and focal length, a tag's corners).
[[nodiscard]] LiveConfig with_source_model(LiveConfig cfg, const FrameSource& source);

/// Camera frame (+x right, +y down, +z away from the camera) to the audio
/// world frame of a listener facing the camera: right is the camera's -x, up
/// its -y, ahead (-z) towards the camera.
[[nodiscard]] Mat3 camera_to_audio();

/// The rotation that turns `down` (gravity direction in the camera frame) into
/// the camera's +y, by the shortest arc: levels a tilted camera.
[[nodiscard]] Mat3 leveling_rotation(const Vec3& down);

/// Seconds since std::chrono::steady_clock's epoch: what HeadPose::steady_s holds.
[[nodiscard]] double steady_clock_s();

struct PipelineCounters {
  std::uint64_t frames = 0, poses = 0, notes = 0;
  std::uint64_t rejected_dots = 0;  ///< NaN or outside the image: never trusted
};

class LivePipeline {
 public:
  explicit LivePipeline(LiveConfig cfg = {});

  /// One event in; the pose to publish (nullopt only for events that carry
  /// no time). `now_s` is the source-clock time of a note (frames and poses
  /// carry their own).
  std::optional<HeadPose> process(const SourceEvent& e, double now_s);

  /// The next camera frame or direct pose becomes the reference (neutral).
  void request_recenter() { recenter_pending_ = true; }

  /// Uses another camera (and beacon model, when given) from the next frame
  /// on: a source that reconnected in another mode. The trackers start afresh
  /// when anything changed; the recenter reference stays.
  void use_camera(const Camera& camera, const std::optional<LedModel>& model);
  [[nodiscard]] const LiveConfig& config() const { return cfg_; }

  [[nodiscard]] PoseState state() const { return state_; }
  [[nodiscard]] const Mat3& leveling() const { return level_; }
  [[nodiscard]] const PipelineCounters& counters() const { return counters_; }
  [[nodiscard]] const TrackResult& last_track() const { return last_track_; }

  /// The clock that stamps HeadPose::steady_s on every pose put out (when
  /// the pose is computed: the frame has just arrived). Tests replace it
  /// to stay deterministic.
  void set_steady_clock(double (*clock)()) { steady_clock_ = clock; }

 private:
  std::optional<HeadPose> on_frame(const CameraFrame& f);
  std::optional<HeadPose> on_pose(const HeadPose& p);
  HeadPose on_note(const SourceNote& n, double now);
  void update_level(const Vec3& accel_cam_g);
  /// World pose of a good measurement -> published pose (recenter, resume blend).
  HeadPose good(double t, const Pose& head, PoseState s);
  HeadPose lost_pose(double t);
  HeadPose emit(double t, const Pose& w, PoseState s);

  LiveConfig cfg_;
  DotTracker tracker_;
  LabelledTracker labelled_;
  TrackResult last_track_;
  Mat3 level_ = Mat3::Identity();
  Vec3 accel_mean_ = Vec3::Zero();
  int still_count_ = 0;
  std::uint16_t buttons_ = 0;
  bool recenter_pending_ = false;
  // Poses in the audio world frame from here on (t in metres, not mm).
  std::optional<Pose> reference_;  ///< the head pose captured at recenter
  bool direct_ = false;                 ///< the reference is in audio axes already
  PoseState state_ = PoseState::searching;
  Pose out_;                            ///< the last published listener pose
  double last_good_t_ = 0.0;
  bool resuming_ = false;
  double resume_t_ = 0.0;
  Pose resume_from_;
  PipelineCounters counters_;
  double (*steady_clock_)() = &steady_clock_s;
};

}  // namespace earshot::tracker
