// A head tracker started for a host that plays on: the source a spec names
// (earshot/tracker/live/source_spec.hpp: wiimote, sim, replay:FILE,
// opentrack, osc, webcam...), its tracker thread and the PoseSlot it
// publishes into. The one way every host starts one (the C API's
// esAttachTracker, the LV2 plugins, the OpenAL bridge and preload shim).
//
// Hosts play on whatever the tracker does: no device yet is not an error
// (the source keeps looking and says so in the status), and a replay that
// ends holds its last pose, then eases to straight ahead.
//
// The tracker publishes into a PoseSlot the host owns, so that an audio
// thread may go on reading it while the tracker is replaced. Construction
// and destruction start and join a thread and open devices or sockets:
// never on the audio thread. The audio thread reads the slot (with a
// HeadReader) and may call recenter() (an atomic flag).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "earshot/pose_slot.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/tracker/live/tracker_options.hpp"

namespace earshot::head {

class TrackedHead {
 public:
  /// Starts the tracker `spec` names, publishing into `slot` (which must
  /// outlive it), with `options` (where its poses are also sent:
  /// tracker/send). Throws earshot::InputError naming `field` for a bad
  /// spec, and what the source throws (a UDP port in use, an unreadable
  /// file). `on_pose` runs on the tracker thread after each publication
  /// (keep it short).
  TrackedHead(std::string_view spec, PoseSlot& slot, const tracker::TrackerOptions& options = {},
              std::string_view field = "tracker", tracker::LiveTracker::PoseCallback on_pose = {});
  ~TrackedHead();  ///< stops and joins the tracker thread
  TrackedHead(const TrackedHead&) = delete;
  TrackedHead& operator=(const TrackedHead&) = delete;

  [[nodiscard]] const std::string& spec() const { return spec_; }
  /// The next pose becomes straight ahead (any thread, real-time safe).
  void recenter() { tracker_->recenter(); }
  [[nodiscard]] tracker::LiveTracker& tracker() { return *tracker_; }
  [[nodiscard]] const tracker::LiveTracker& tracker() const { return *tracker_; }

  /// The camera image the dots are in, as the source said when it started:
  /// 0 x 0 for a source that sends poses and a webcam not opened yet.
  [[nodiscard]] int camera_width() const { return camera_width_; }
  [[nodiscard]] int camera_height() const { return camera_height_; }

 private:
  std::string spec_;
  int camera_width_ = 0, camera_height_ = 0;
  std::unique_ptr<tracker::LiveTracker> tracker_;
};

}  // namespace earshot::head
