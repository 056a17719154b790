#include "shared_tracker.hpp"

#include "earshot/tracker/live/source_spec.hpp"
#include "earshot/tracker/send/send_spec.hpp"

namespace earshot::lv2 {

SharedTrackers& SharedTrackers::process() {
  static SharedTrackers registry;  // a cache of running trackers, guarded by its mutex
  return registry;
}

std::shared_ptr<TrackerLease> SharedTrackers::acquire(const std::string& spec, const std::string& send,
                                                     std::string* note) {
  const auto parsed = tracker::parse_source_spec(spec, "tracker");
  tracker::LiveConfig cfg;
  cfg.send = tracker::parse_send_list(send, "send");
  std::lock_guard lock(mutex_);
  if (auto held = leases_[spec].lock()) {
    if (note && held->send != send)
      *note = "tracker '" + spec + "' already runs in this process, sending to '" + held->send +
              "' (another instance started it); instances that share a tracker share where it sends, so '" + send +
              "' is not used";
    return held;
  }
  auto lease = std::make_shared<TrackerLease>();
  lease->spec = spec;
  lease->send = send;
  tracker::SourceOptions options;
  options.wait_for_remote = true;  // no remote yet: the plugin plays on, the tracker keeps looking
  lease->tracker =
      std::make_unique<tracker::LiveTracker>(tracker::make_frame_source(parsed, options), lease->slot, cfg);
  leases_[spec] = lease;
  return lease;
}

std::size_t SharedTrackers::running() {
  std::lock_guard lock(mutex_);
  std::size_t n = 0;
  for (auto it = leases_.begin(); it != leases_.end();) {
    if (it->second.expired()) {
      it = leases_.erase(it);
    } else {
      ++n;
      ++it;
    }
  }
  return n;
}

}  // namespace earshot::lv2
