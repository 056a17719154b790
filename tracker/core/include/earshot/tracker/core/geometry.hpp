// Geometry vocabulary of the tracker: vectors, rigid poses and the angle
// conventions used to describe them to people.
//
// A beacon pose maps model points (mm) into the camera frame (mm):
//     P_cam = R * P_model + t
// Camera frame: +x right, +y down, +z forward along the optical axis.
//
// Eigen stays inside the tracker (its solvers need matrices); poses leave
// it as the common earshot::Vec3 / earshot::Quat (earshot/geometry.hpp),
// converted by to_common and to_eigen.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "earshot/geometry.hpp"

namespace earshot::tracker {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Rigid transform from the beacon model frame to the camera frame (mm).
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();

  [[nodiscard]] Vec3 apply(const Vec3& p) const { return R * p + t; }
  [[nodiscard]] Quat quaternion() const;  ///< unit quaternion, w >= 0
  [[nodiscard]] static Pose from(const Quat& q, const Vec3& t);
  [[nodiscard]] bool finite() const { return R.allFinite() && t.allFinite(); }
};

/// Between the tracker's Eigen types and the common arrays (quaternions
/// w, x, y, z in both; no normalisation, no change of frame).
[[nodiscard]] inline earshot::Vec3 to_common(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
[[nodiscard]] inline earshot::Quat to_common(const Quat& q) { return {q.w(), q.x(), q.y(), q.z()}; }
[[nodiscard]] inline Vec3 to_eigen(const earshot::Vec3& v) { return {v[0], v[1], v[2]}; }
[[nodiscard]] inline Quat to_eigen(const earshot::Quat& q) { return {q[0], q[1], q[2], q[3]}; }

/// Skew-symmetric matrix [v]x with [v]x * u = v x u.
[[nodiscard]] Mat3 skew(const Vec3& v);

/// Rotation matrix exp([w]x) for a rotation vector w (radians).
[[nodiscard]] Mat3 exp_so3(const Vec3& w);

/// Rotation vector of R (inverse of exp_so3), |result| <= pi.
[[nodiscard]] Vec3 log_so3(const Mat3& R);

/// Angle (radians) of the relative rotation between a and b.
[[nodiscard]] double rotation_angle_between(const Mat3& a, const Mat3& b);

/// Re-orthonormalise a nearly orthonormal matrix (nearest rotation, det +1).
[[nodiscard]] Mat3 nearest_rotation(const Mat3& M);

/// Beacon rotation from yaw, pitch, roll (radians), in the camera frame:
/// R = Ry(yaw) * Rx(pitch) * Rz(roll).
[[nodiscard]] Mat3 rotation_from_ypr(double yaw, double pitch, double roll);

}  // namespace earshot::tracker
