#include "earshot/host/rooms.hpp"

#include "earshot/audio/room_presets.hpp"

namespace earshot::host {

std::vector<std::string> room_names() {
  std::vector<std::string> r{"none"};
  for (const auto& p : audio::room_presets()) r.emplace_back(p.name);
  return r;
}

}  // namespace earshot::host
