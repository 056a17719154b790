// Quaternions (w, x, y, z) for the listener: OpenAL's "at"/"up" pair to a
// rotation, composition, and rotating a vector. Shared by the plugin and
// the OpenAL bridge.
#pragma once

#include <array>
#include <cmath>
#include <optional>

namespace earshot::plugin {

using Quat4 = std::array<double, 4>;
using Vec3d = std::array<double, 3>;

[[nodiscard]] inline Quat4 multiply(const Quat4& a, const Quat4& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

[[nodiscard]] inline Vec3d rotate(const Quat4& q, const Vec3d& v) {
  const Quat4 r = multiply(multiply(q, Quat4{0, v[0], v[1], v[2]}), Quat4{q[0], -q[1], -q[2], -q[3]});
  return {r[1], r[2], r[3]};
}

/// The rotation taking the listener's rest frame (-z ahead, +y up) to
/// "at" and "up" (OpenAL's AL_ORIENTATION; up need not be orthogonal to at).
/// nullopt when either is zero or not finite, or they are parallel.
[[nodiscard]] inline std::optional<Quat4> quat_from_at_up(const Vec3d& at_in, const Vec3d& up_in) {
  auto normalised = [](Vec3d v) -> std::optional<Vec3d> {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!std::isfinite(n) || !(n > 1e-12)) return std::nullopt;
    return Vec3d{v[0] / n, v[1] / n, v[2] / n};
  };
  auto cross = [](const Vec3d& a, const Vec3d& b) {
    return Vec3d{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto at = normalised(at_in), up0 = normalised(up_in);
  if (!at || !up0) return std::nullopt;
  const auto right = normalised(cross(*at, *up0));
  if (!right) return std::nullopt;
  const Vec3d up = cross(*right, *at);
  // Rotation matrix with columns right, up, back (= -at).
  const double m00 = (*right)[0], m01 = up[0], m02 = -(*at)[0];
  const double m10 = (*right)[1], m11 = up[1], m12 = -(*at)[1];
  const double m20 = (*right)[2], m21 = up[2], m22 = -(*at)[2];
  const double tr = m00 + m11 + m22;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    return Quat4{0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  }
  if (m00 > m11 && m00 > m22) {
    const double s = std::sqrt(1.0 + m00 - m11 - m22) * 2;
    return Quat4{(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  }
  if (m11 > m22) {
    const double s = std::sqrt(1.0 + m11 - m00 - m22) * 2;
    return Quat4{(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  }
  const double s = std::sqrt(1.0 + m22 - m00 - m11) * 2;
  return Quat4{(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
}

/// A finite, non-zero quaternion scaled to unit length; nullopt otherwise.
[[nodiscard]] inline std::optional<Quat4> normalised(const Quat4& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(n) || !(n > 1e-6)) return std::nullopt;
  return Quat4{q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

}  // namespace earshot::plugin
