// The rooms a scene can name: "none" and the plugin's room presets
// (audio/room_presets.hpp, esReverbPreset's names).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace earshot::host {

/// "none", then every room preset.
[[nodiscard]] std::vector<std::string> room_names();
// Checking a room name given outside Scene JSON: scenes::checked_room_name.

}  // namespace earshot::host
