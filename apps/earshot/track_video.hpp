// `earshot track simulate-video`: synthetic webcam video of a head walk
// (LED beacon or AprilTag) as a Y4M file plus its ground truth.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {

/// Adds `track simulate-video` to `track`.
void add_track_video_commands(CLI::App& track);

}  // namespace earshot::app
