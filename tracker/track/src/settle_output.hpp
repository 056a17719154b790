// The last step of every tracker's frame (DotTracker, LabelledTracker).
#pragma once

#include <optional>

#include "earshot/tracker/track/dot_tracker.hpp"

namespace earshot::tracker::detail {

/// A lost frame holds the last pose given out, a pose that is not finite is
/// never passed on (the frame counts as lost), and the pose given out is
/// remembered for the next lost frame.
inline void settle_output(TrackResult& r, std::optional<Pose>& last_output) {
  if (r.state == PoseState::lost && last_output) r.pose = *last_output;
  if (!r.pose.finite()) {
    r.state = PoseState::lost;
    r.pose = last_output.value_or(Pose{});
  }
  r.has_pose = r.state != PoseState::lost || last_output.has_value();
  if (r.state != PoseState::lost) last_output = r.pose;
}

}  // namespace earshot::tracker::detail
