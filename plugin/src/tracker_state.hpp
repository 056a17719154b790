// The live tracker's status (tracker::LiveTracker::Status, copied on the
// control thread) as the C API's EStrackerstate: one state out of the
// pipeline's pose state, the source's link notes and whether it ended, the
// rate, the newest frame's dots with their labels, and a message for people.
// Also the source's picture (tracker::Thumbnail) as EStrackerimage.
// Pure, so tests map a scripted session's status without a world.
#pragma once

#include "earshot/earshot.h"
#include "earshot/tracker/live/live_tracker.hpp"

namespace earshot::plugin {

/// `status` null: no tracker attached. Writes every field of `out` but `size`.
void fill_tracker_state(const tracker::LiveTracker::Status* status, EStrackerstate& out);

/// `thumb` null: no picture. `camera_width` x `camera_height`: the source
/// camera's image (0 x 0: none). Writes every field of `out` but `size`.
void fill_tracker_image(const tracker::Thumbnail* thumb, int camera_width, int camera_height, EStrackerimage& out);

}  // namespace earshot::plugin
