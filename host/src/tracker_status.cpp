#include "earshot/host/tracker_status.hpp"

namespace earshot::host {

const char* tracker_state_name(ESenum state) {
  switch (state) {
    case ES_TRACKER_NONE: return "none";
    case ES_TRACKER_SEARCHING: return "searching";
    case ES_TRACKER_CONNECTED: return "connected";
    case ES_TRACKER_TRACKING: return "tracking";
    case ES_TRACKER_LOST: return "lost";
    case ES_TRACKER_DISCONNECTED: return "disconnected";
    default: return "?";
  }
}

void TrackerStatus::refresh(ESworld world) {
  if (!failed.empty()) {
    state = "failed", message = failed + "; the head is held straight", alarm = true;
    return;
  }
  raw = EStrackerstate{};
  raw.size = sizeof raw;
  if (esGetTrackerState(world, &raw) != ES_OK) return;
  state = tracker_state_name(raw.state), message = raw.message;
  // Searching is news only when nothing can be found or opened; a
  // disconnected remote always is.
  const std::string m = raw.message;
  alarm = raw.state == ES_TRACKER_SEARCHING
              ? m.find("no Wii Remote") != std::string::npos || m.find("permission") != std::string::npos
              : raw.state == ES_TRACKER_DISCONNECTED;
  if (raw.state == ES_TRACKER_NONE) message.clear();
}

TrackerStatus attach_tracker(ESworld world, const std::string& spec, const std::vector<std::string>& send) {
  TrackerStatus t;
  t.spec = spec.empty() ? "none" : spec;
  if (t.spec == "none") return t;
  std::vector<const char*> options;
  for (const std::string& s : send) options.insert(options.end(), {"send", s.c_str()});
  options.push_back(nullptr);
  if (esAttachTrackerEx(world, spec.c_str(), options.data()) != ES_OK)
    t.failed = esGetErrorMessage(world);
  else
    (void)esRecenter(world);
  return t;
}

}  // namespace earshot::host
