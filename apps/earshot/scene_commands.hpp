// `earshot scene ...`: looking at Scene JSON without rendering it.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {

/// Adds `scene list` (the shipped presets and their stories) and `scene paths`
/// (where every source is over time, as CSV) under `scene`.
void add_scene_commands(CLI::App& scene);

}  // namespace earshot::app
