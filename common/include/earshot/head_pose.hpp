// The head pose: what the tracker hands the renderer, and all it hands it.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

namespace earshot {

enum class PoseState : std::uint8_t { searching, tracking, predicted, lost };

/// Listener head pose in the audio world frame (OpenAL's: +x right, +y up,
/// -z ahead), metres, unit quaternion (w, x, y, z). Trivially copyable.
struct HeadPose {
  double t = 0.0;                                  ///< seconds, tracker clock
  std::array<double, 3> position{0.0, 0.0, 0.0};   ///< metres
  std::array<double, 4> orientation{1.0, 0.0, 0.0, 0.0};  ///< w, x, y, z
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
