// A head tracker attached to a world (esAttachTracker), and its state as a
// host's UI shows it: a name, the tracker's message, and whether the person
// must act (no Wii Remote found, no permission, disconnected, failed).
#pragma once

#include <string>
#include <vector>

#include "earshot/earshot.h"

namespace earshot::host {

/// "none", "searching", "connected", "tracking", "lost", "disconnected" ("?": unknown).
[[nodiscard]] const char* tracker_state_name(ESenum state);

/// The tracker as a host shows it, refreshed from the control thread.
struct TrackerStatus {
  std::string spec = "none";   ///< as given ("sim", "wiimote", "none", ...)
  std::string failed;          ///< esAttachTracker's refusal ("": attached or none)
  std::string state = "none";  ///< tracker_state_name, or "failed"
  std::string message;         ///< for people; "" when there is nothing to say
  bool alarm = false;          ///< the person must act: show it loudly
  EStrackerstate raw{};        ///< the plugin's last esGetTrackerState

  /// Reads the world's tracker state (control thread).
  void refresh(ESworld world);
};

/// Attaches the tracker `spec` ("", "none": no tracker) and recenters it, so
/// the first pose is straight ahead; `send`: where it also sends its poses
/// (esAttachTrackerEx's "send" options). A refusal is no error: the returned
/// status says why (`failed`) and the head is held straight.
[[nodiscard]] TrackerStatus attach_tracker(ESworld world, const std::string& spec,
                                           const std::vector<std::string>& send = {});

}  // namespace earshot::host
