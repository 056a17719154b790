// `earshot track calibrate`: LED-model self-calibration from a recorded session.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {

/// Adds `track calibrate` to `track`.
void add_track_calibrate_command(CLI::App& track);

}  // namespace earshot::app
