#include "shared_tracker.hpp"

#include "earshot/tracker/live/source_spec.hpp"

namespace earshot::lv2 {

SharedTrackers& SharedTrackers::process() {
  static SharedTrackers registry;  // a cache of running trackers, guarded by its mutex
  return registry;
}

std::shared_ptr<TrackerLease> SharedTrackers::acquire(const std::string& spec) {
  (void)tracker::parse_source_spec(spec, "tracker");  // a bad spec throws before anything is registered
  std::lock_guard lock(mutex_);
  if (auto held = leases_[spec].lock()) return held;
  auto lease = std::make_shared<TrackerLease>();
  lease->head = std::make_unique<head::TrackedHead>(spec, lease->slot);
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
