// The head pose: what the tracker hands the renderer, and all it hands it.
#pragma once

#include <algorithm>
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
  double t = 0.0;                    ///< seconds, the source's own clock (differs per source)
  Vec3 position{0.0, 0.0, 0.0};      ///< metres
  Quat orientation = kIdentityQuat;  ///< w, x, y, z
  PoseState state = PoseState::searching;
  std::uint64_t sequence = 0;  ///< increases with every publication
  /// The head's motion as the tracker's filter estimates it (zero when it
  /// has none): angular velocity in rad/s in the world frame (a moment dt
  /// later the orientation is the rotation by angle |w| dt about w, applied
  /// after `orientation`) and velocity in m/s.
  Vec3 angular_velocity{0.0, 0.0, 0.0};
  Vec3 velocity{0.0, 0.0, 0.0};
  /// When the pose held, on std::chrono::steady_clock (seconds since its
  /// epoch): the clock the tracker thread and the audio thread share, which
  /// `t` is not. 0: unknown (the pose is never extrapolated).
  double steady_s = 0.0;

  [[nodiscard]] bool finite() const {
    for (const Vec3* v : {&position, &angular_velocity, &velocity})
      for (double x : *v)
        if (!std::isfinite(x)) return false;
    for (double v : orientation)
      if (!std::isfinite(v)) return false;
    return std::isfinite(t) && std::isfinite(steady_s);
  }
};

/// How far ahead the audio side extrapolates a head pose at most: a head
/// turning at 500 deg/s moves 30 deg in 60 ms, and constant velocity stops
/// being a fair guess beyond a few tens of milliseconds (a head's quick turns
/// last ~100-200 ms).
inline constexpr double kMaxHeadPredictionS = 0.060;

/// `p` carried forward at its own constant angular and linear velocity to
/// steady-clock time `at_s` (the time the audio block will be heard): on
/// SO(3) x R3, orientation <- exp(w dt) * orientation, position <- position
/// + v dt, with dt = at_s - p.steady_s clamped to [0, max_ahead_s]. Only a
/// pose in the tracking state with a known steady_s is extrapolated; a
/// predicted, lost or searching one is returned as it is (the tracker is
/// already bridging a gap or easing). Real-time safe: arithmetic only.
[[nodiscard]] inline HeadPose extrapolate(const HeadPose& p, double at_s, double max_ahead_s = kMaxHeadPredictionS) {
  if (p.state != PoseState::tracking || !(p.steady_s > 0.0)) return p;
  const double dt = std::clamp(at_s - p.steady_s, 0.0, std::max(0.0, max_ahead_s));
  if (!(dt > 0.0)) return p;
  HeadPose out = p;
  for (int i = 0; i < 3; ++i) out.position[i] += p.velocity[i] * dt;
  const Vec3 half{0.5 * dt * p.angular_velocity[0], 0.5 * dt * p.angular_velocity[1], 0.5 * dt * p.angular_velocity[2]};
  const double a = norm(half);  // half the angle turned
  const double s = a > 1e-12 ? std::sin(a) / a : 1.0;
  const Quat turn{std::cos(a), s * half[0], s * half[1], s * half[2]};
  out.orientation = normalised(multiply(turn, p.orientation)).value_or(p.orientation);
  out.steady_s = p.steady_s + dt;
  return out;
}

}  // namespace earshot
