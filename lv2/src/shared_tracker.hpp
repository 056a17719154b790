// The process's head trackers, shared: every plugin instance in one host
// process that asks for the same tracker spec follows the same head (one
// Wii Remote, one UDP port, one tracker thread), and the tracker stops when
// the last instance lets go.
//
// acquire() and dropping a lease start and join threads and open sockets:
// call them off the audio thread (the plugin does, in its LV2 worker). The
// audio thread only reads the lease's PoseSlot (lock-free) and may ask for a
// recenter (an atomic flag).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "earshot/pose_slot.hpp"
#include "earshot/head/tracked_head.hpp"

namespace earshot::lv2 {

/// One running tracker and the slot it publishes into.
struct TrackerLease {
  std::string send;  ///< where it sends its poses (tracker/send's ';' list), as it was started
  PoseSlot slot;  // declared before the tracker: it outlives the tracker thread
  std::unique_ptr<head::TrackedHead> head;
};

class SharedTrackers {
 public:
  /// The registry of this process (one per loaded plugin library).
  static SharedTrackers& process();

  /// The running tracker for `spec` (tracker/live/source_spec.hpp, e.g. "wiimote",
  /// "osc:9000"), started if no instance holds one, sending its poses to
  /// `send` (tracker/send/send_spec.hpp, ';'-separated; "" nowhere). Throws
  /// InputError for a bad spec or send list and what the source or a sender
  /// throws (a UDP port in use, a host that does not resolve).
  /// One tracker per spec: instances sharing it share where it sends. The
  /// first to start it decides; a later one asking another send list gets
  /// the running tracker and a `note` saying so (for the host's log).
  [[nodiscard]] std::shared_ptr<TrackerLease> acquire(const std::string& spec, const std::string& send = {},
                                                      std::string* note = nullptr);

  /// Trackers running now (tests).
  [[nodiscard]] std::size_t running();

 private:
  std::mutex mutex_;
  std::map<std::string, std::weak_ptr<TrackerLease>> leases_;
};

}  // namespace earshot::lv2
