// The rooms a scene can name: "none" and the plugin's room presets
// (audio/room_presets.hpp, esReverbPreset's names).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace earshot::host {

/// "none", then every room preset.
[[nodiscard]] std::vector<std::string> room_names();

/// `room` when it is "none" or a preset; else throws earshot::InputError
/// "origin: unknown room preset 'x' (available: none, ...)".
[[nodiscard]] std::string checked_room(std::string_view room, std::string_view origin);

}  // namespace earshot::host
