// What a host asks of a tracker beyond its source spec, as name/value pairs
// (the C API's esAttachTrackerEx takes them as a NULL-terminated list, in
// OpenAL's attribute-list style; the CLI, the demo and the LV2 plugins build
// the same struct from their own options):
//
//   "send", SPEC    send every pose on (tracker/send/send_spec.hpp); repeatable
//
// One parser for every host, so an option means the same everywhere.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/send/send_spec.hpp"

namespace earshot::tracker {

/// The option names, for messages.
inline constexpr std::string_view kTrackerOptionNames = "send";

struct TrackerOptions {
  std::vector<SendSpec> send;

  friend bool operator==(const TrackerOptions&, const TrackerOptions&) = default;
};

/// Parses name/value pairs. Throws earshot::InputError naming `field` and
/// the option for an unknown name or a bad value (the value's own error).
[[nodiscard]] TrackerOptions parse_tracker_options(const std::vector<std::pair<std::string, std::string>>& pairs,
                                                   std::string_view field = "tracker options");

/// `cfg` with the options applied (what LiveTracker reads of them).
[[nodiscard]] LiveConfig with_options(LiveConfig cfg, const TrackerOptions& options);

}  // namespace earshot::tracker
