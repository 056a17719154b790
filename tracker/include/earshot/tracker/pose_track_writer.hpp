// The old name of the Pose track CSV writer, kept until the demo
// (apps/earshot/demo_command.cpp) includes pose_track_csv.hpp itself.
#pragma once

#include "earshot/tracker/pose_track_csv.hpp"

namespace earshot::tracker {
using PoseTrackWriter = PoseTrackCsvWriter;
}  // namespace earshot::tracker
