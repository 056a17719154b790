#include "earshot/host/rooms.hpp"

#include "earshot/audio/room_presets.hpp"
#include "earshot/errors.hpp"

namespace earshot::host {

std::vector<std::string> room_names() {
  std::vector<std::string> r{"none"};
  for (const auto& p : audio::room_presets()) r.emplace_back(p.name);
  return r;
}

std::string checked_room(std::string_view room, std::string_view origin) {
  for (const auto& name : room_names())
    if (name == room) return name;
  throw InputError::at(origin, 0, "",
                       "unknown room preset '" + std::string(room) + "' (available: none, " +
                           audio::room_preset_names() + ")");
}

}  // namespace earshot::host
