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
  // A bad spec or send list throws before anything is registered.
  (void)tracker::parse_source_spec(spec, "tracker");
  tracker::TrackerOptions options;
  options.send = tracker::parse_send_list(send, "send");
  std::lock_guard lock(mutex_);
  if (auto held = leases_[spec].lock()) {
    if (note && held->send != send)
      *note = "tracker '" + spec + "' already runs in this process, sending to '" + held->send +
              "' (another instance started it); instances that share a tracker share where it sends, so '" + send +
              "' is not used";
    return held;
  }
  auto lease = std::make_shared<TrackerLease>();
  lease->send = send;
  lease->head = std::make_unique<head::TrackedHead>(spec, lease->slot, options);
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
