// `earshot track ...`: simulate, solve and summarise head tracking runs.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {

/// Adds `track simulate` and `track solve` to `track`.
void add_track_commands(CLI::App& track);

/// Adds `track live` and `track record` (track_live.cpp).
void add_track_live_commands(CLI::App& track);

}  // namespace earshot::app
