#include "earshot/tracker/live/tracker_options.hpp"

#include "earshot/errors.hpp"

namespace earshot::tracker {

TrackerOptions parse_tracker_options(const std::vector<std::pair<std::string, std::string>>& pairs,
                                     std::string_view field) {
  TrackerOptions o;
  for (const auto& [name, value] : pairs) {
    if (name == "send") {
      o.send.push_back(parse_send_spec(value, field));
    } else {
      throw InputError::at(field, 0, "",
                           "unknown option '" + name + "' (" + std::string(kTrackerOptionNames) + ")");
    }
  }
  return o;
}

LiveConfig with_options(LiveConfig cfg, const TrackerOptions& options) {
  cfg.send = options.send;
  return cfg;
}

}  // namespace earshot::tracker
