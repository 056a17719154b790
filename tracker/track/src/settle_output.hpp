// The last step of every tracker's frame (DotTracker, LabelledTracker).
#pragma once

#include <cmath>
#include <optional>

#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/filter/motion_reach.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"

namespace earshot::tracker::detail {

/// A lost frame holds the last pose given out as tracked (never a predicted
/// one: a held prediction is off by all it extrapolated), a pose that is
/// not finite is never passed on (the frame counts as lost), and the
/// tracked pose given out is remembered for the next lost frame.
inline void settle_output(TrackResult& r, std::optional<Pose>& last_tracked) {
  if (r.state == PoseState::lost && last_tracked) r.pose = *last_tracked;
  if (!r.pose.finite()) {
    r.state = PoseState::lost;
    r.pose = last_tracked.value_or(Pose{});
  }
  r.has_pose = r.state != PoseState::lost || last_tracked.has_value();
  if (r.state == PoseState::tracking) last_tracked = r.pose;
}

/// A prediction worth giving out: it moves the pose at most `reach` (rad)
/// from the last tracked output, and with the eskf its rotation spread
/// (the root of the trace of the predicted covariance's rotation block)
/// stays within it too.
inline bool within_reach(const Pose& predicted, const Pose& last_tracked, const PoseEskf* eskf, double t, double reach) {
  if (!(rotation_angle_between(predicted.R, last_tracked.R) <= reach)) return false;
  if (eskf)
    if (const auto spread = eskf->predicted_pose_covariance(t))
      if (!(std::sqrt(spread->topLeftCorner<3, 3>().trace()) <= reach)) return false;
  return true;
}

}  // namespace earshot::tracker::detail
