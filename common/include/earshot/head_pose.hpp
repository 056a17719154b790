// The head pose: what the tracker hands the renderer, and all it hands it.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

#include "earshot/geometry.hpp"

namespace earshot {

/// What a tracker knows about the head: looking for it, seeing it, carrying
/// the last motion on through a short gap, or having lost it. The tracker's
/// per-frame result, the live pose and the Poses CSV all use this one enum.
enum class PoseState : std::uint8_t { searching, tracking, predicted, lost };

/// "searching", "tracking", "predicted", "lost": the spelling in files and on screen.
[[nodiscard]] constexpr std::string_view pose_state_name(PoseState s) {
  switch (s) {
    case PoseState::searching: return "searching";
    case PoseState::tracking: return "tracking";
    case PoseState::predicted: return "predicted";
    case PoseState::lost: return "lost";
  }
  return "lost";
}

/// The state spelled `name` (exactly as pose_state_name gives it), if any.
[[nodiscard]] constexpr std::optional<PoseState> pose_state_from_name(std::string_view name) {
  for (auto s : {PoseState::searching, PoseState::tracking, PoseState::predicted, PoseState::lost})
    if (pose_state_name(s) == name) return s;
  return std::nullopt;
}

/// Listener head pose in the audio world frame (OpenAL's: +x right, +y up,
/// -z ahead), metres, unit quaternion (w, x, y, z). Trivially copyable.
struct HeadPose {
  double t = 0.0;                                  ///< seconds, tracker clock
  Vec3 position{0.0, 0.0, 0.0};   ///< metres
  Quat orientation = kIdentityQuat;  ///< w, x, y, z
  PoseState state = PoseState::searching;
  std::uint64_t sequence = 0;  ///< increases with every publication

  [[nodiscard]] bool finite() const {
    for (double v : position)
      if (!std::isfinite(v)) return false;
    for (double v : orientation)
      if (!std::isfinite(v)) return false;
    return std::isfinite(t);
  }
};

}  // namespace earshot
