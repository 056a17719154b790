// The geometry vocabulary every module speaks: a 3-vector and a unit
// quaternion as plain arrays of doubles, and the few operations on them.
//
// Frame: the audio world frame, OpenAL's: +x right, +y up, -z ahead,
// metres. A quaternion (w, x, y, z) is a rotation; an orientation rotates
// the head's rest frame (looking along -z, +y up) into the world, so
// rotate(q, {0, 0, -1}) is where the head looks.
//
// Yaw, pitch, roll (radians) describe an orientation to people:
//   q = q_yaw * q_pitch * q_roll, applied right to left to the rest frame:
//   roll about the view axis (roll > 0 tilts the head to the right: up
//   leans towards +x), then pitch about +x (pitch > 0 looks up), then yaw
//   about +y (yaw > 0 turns left: ahead swings towards -x).
//
// The tracker solves in Eigen in the camera frame (tracker/core/geometry.hpp)
// and converts to these types where a pose leaves it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace earshot {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  ///< w, x, y, z

inline constexpr Quat kIdentityQuat{1.0, 0.0, 0.0, 0.0};

[[nodiscard]] constexpr double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

[[nodiscard]] constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

[[nodiscard]] inline double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }

/// The Hamilton product: multiply(a, b) rotates by b first, then by a.
[[nodiscard]] constexpr Quat multiply(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

/// The inverse rotation of a unit quaternion.
[[nodiscard]] constexpr Quat conjugate(const Quat& q) { return {q[0], -q[1], -q[2], -q[3]}; }

/// v rotated by unit quaternion q (q v q*), without forming the products:
/// t = 2 (q.xyz x v); v' = v + w t + q.xyz x t.
[[nodiscard]] constexpr Vec3 rotate(const Quat& q, const Vec3& v) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)};
}

/// v rotated by the inverse of q: a world direction seen from the head.
[[nodiscard]] constexpr Vec3 rotate_inverse(const Quat& q, const Vec3& v) { return rotate(conjugate(q), v); }

/// A finite, non-zero quaternion scaled to unit length; nullopt otherwise.
[[nodiscard]] inline std::optional<Quat> normalised(const Quat& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(n) || !(n > 1e-6)) return std::nullopt;
  return Quat{q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

/// Spherical interpolation of unit quaternions along the shorter arc: a at
/// u = 0, b (or -b, the same rotation) at u = 1, unit length throughout.
/// Nearly equal rotations are blended linearly and renormalised.
[[nodiscard]] inline Quat slerp(const Quat& a, const Quat& b, double u) {
  Quat qb = b;
  double d = 0;
  for (std::size_t i = 0; i < 4; ++i) d += a[i] * qb[i];
  if (d < 0) {
    for (double& c : qb) c = -c;
    d = -d;
  }
  double wa = 1 - u, wb = u;
  if (d < 0.9995) {
    const double th = std::acos(std::min(1.0, d));
    wa = std::sin((1 - u) * th) / std::sin(th);
    wb = std::sin(u * th) / std::sin(th);
  }
  Quat out;
  double n2 = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = wa * a[i] + wb * qb[i];
    n2 += out[i] * out[i];
  }
  for (double& c : out) c /= std::sqrt(n2);
  return out;
}

/// The orientation with these yaw, pitch and roll (radians; see the top).
[[nodiscard]] inline Quat quat_from_ypr(double yaw, double pitch, double roll) {
  const Quat qy{std::cos(yaw / 2), 0, std::sin(yaw / 2), 0};
  const Quat qp{std::cos(pitch / 2), std::sin(pitch / 2), 0, 0};
  const Quat qr{std::cos(roll / 2), 0, 0, -std::sin(roll / 2)};
  return multiply(multiply(qy, qp), qr);
}

struct YawPitchRoll {
  double yaw = 0.0, pitch = 0.0, roll = 0.0;  ///< radians
};

/// Yaw, pitch, roll of a unit quaternion (the inverse of quat_from_ypr):
/// yaw in (-pi, pi], pitch in [-pi/2, pi/2], roll in (-pi, pi]. Looking
/// straight up or down (gimbal lock) only yaw -/+ roll is defined: roll is
/// reported as 0 and the whole turn as yaw.
[[nodiscard]] inline YawPitchRoll ypr_from_quat(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // Entries of the rotation matrix R (rest frame -> world) that are needed.
  const double r00 = 1 - 2 * (y * y + z * z), r02 = 2 * (x * z + w * y);
  const double r10 = 2 * (x * y + w * z), r11 = 1 - 2 * (x * x + z * z), r12 = 2 * (y * z - w * x);
  const double r20 = 2 * (x * z - w * y), r22 = 1 - 2 * (x * x + y * y);
  YawPitchRoll a;
  // R = Ry(yaw) Rx(pitch) Rz(-roll): row 1 is (cos p sin -r, cos p cos -r, -sin p).
  const double cos_pitch = std::hypot(r10, r11);
  a.pitch = std::atan2(-r12, cos_pitch);
  if (cos_pitch > 1e-9) {
    a.yaw = std::atan2(r02, r22);  // from where the head looks: ahead = -R e_z
    a.roll = -std::atan2(r10, r11);
  } else {
    a.yaw = std::atan2(-r20, r00);  // the right ear's direction R e_x, roll 0
  }
  return a;
}

/// The rotation taking the rest frame (-z ahead, +y up) to "at" and "up"
/// (OpenAL's AL_ORIENTATION pair; up need not be orthogonal to at).
/// nullopt when either is zero or not finite, or they are parallel.
[[nodiscard]] inline std::optional<Quat> quat_from_at_up(const Vec3& at_in, const Vec3& up_in) {
  auto unit = [](const Vec3& v) -> std::optional<Vec3> {
    const double n = norm(v);
    if (!std::isfinite(n) || !(n > 1e-12)) return std::nullopt;
    return Vec3{v[0] / n, v[1] / n, v[2] / n};
  };
  const auto at = unit(at_in), up0 = unit(up_in);
  if (!at || !up0) return std::nullopt;
  const auto right = unit(cross(*at, *up0));
  if (!right) return std::nullopt;
  const Vec3 up = cross(*right, *at);
  // Rotation matrix with columns right, up, back (= -at).
  const double m00 = (*right)[0], m01 = up[0], m02 = -(*at)[0];
  const double m10 = (*right)[1], m11 = up[1], m12 = -(*at)[1];
  const double m20 = (*right)[2], m21 = up[2], m22 = -(*at)[2];
  const double tr = m00 + m11 + m22;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    return Quat{0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  }
  if (m00 > m11 && m00 > m22) {
    const double s = std::sqrt(1.0 + m00 - m11 - m22) * 2;
    return Quat{(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  }
  if (m11 > m22) {
    const double s = std::sqrt(1.0 + m11 - m00 - m22) * 2;
    return Quat{(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  }
  const double s = std::sqrt(1.0 + m22 - m00 - m11) * 2;
  return Quat{(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
}

}  // namespace earshot
