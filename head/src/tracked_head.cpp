#include "earshot/head/tracked_head.hpp"

#include "earshot/tracker/live/source_spec.hpp"

namespace earshot::head {

TrackedHead::TrackedHead(std::string_view spec, PoseSlot& slot, const tracker::TrackerOptions& options,
                         std::string_view field, tracker::LiveTracker::PoseCallback on_pose)
    : spec_(spec) {
  const tracker::SourceSpec parsed = tracker::parse_source_spec(spec, field);
  tracker::SourceOptions source;
  source.wait_for_remote = true;  // no device yet: the host plays on, the source keeps looking
  tracker::LiveConfig cfg = tracker::with_options({}, options);  // where the poses go, too
  cfg.keep_running_after_end = true;  // a replay that ends: hold, then ease to straight ahead
  auto frames = tracker::make_frame_source(parsed, source);
  // The camera the dots are in, asked before the tracker thread owns the
  // source: a webcam's opened size, else the configured (Wii) camera. A
  // source of poses has none; a webcam waiting for its device has no size yet.
  const std::optional<tracker::Camera> own = frames->camera();
  const bool unknown = parsed.sends_poses() || (!own && parsed.kind == tracker::SourceSpec::Kind::webcam);
  const tracker::Camera cam = own.value_or(cfg.camera);
  camera_width_ = unknown ? 0 : cam.width;
  camera_height_ = unknown ? 0 : cam.height;
  tracker_ = std::make_unique<tracker::LiveTracker>(std::move(frames), slot, cfg, std::move(on_pose));
}

TrackedHead::~TrackedHead() = default;

}  // namespace earshot::head
