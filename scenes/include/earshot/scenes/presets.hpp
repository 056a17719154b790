// Shipped preset scenes (scenes/presets/*.json): manual, circles, traffic,
// zoo, teleconference. `earshot render --scene circles` names one: a bare
// name (no '/', no ".json") that is not a file in the working directory is
// looked up as NAME.json in, in order,
//   <directory of the executable>/../share/earshot/scenes   (installed)
//   the source tree's scenes/presets                         (compiled in)
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace earshot::scenes {

/// The directories searched for presets, in order (existing ones only).
[[nodiscard]] std::vector<std::filesystem::path> preset_dirs();

/// Names of the shipped presets found, sorted.
[[nodiscard]] std::vector<std::string> preset_names();

/// The Scene JSON file a --scene argument means: the argument itself when it
/// is a path, else the shipped preset of that name. Throws
/// earshot::InputError naming the argument and listing the presets.
[[nodiscard]] std::filesystem::path resolve_scene_argument(std::string_view arg);

}  // namespace earshot::scenes
