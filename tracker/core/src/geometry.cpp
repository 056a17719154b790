#include "earshot/tracker/core/geometry.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace earshot::tracker {

Quat Pose::quaternion() const {
  Quat q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

Pose Pose::from(const Quat& q, const Vec3& t) { return {q.normalized().toRotationMatrix(), t}; }

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Mat3 exp_so3(const Vec3& w) {
  const double theta2 = w.squaredNorm();
  const Mat3 W = skew(w);
  if (theta2 < 1e-16) return Mat3::Identity() + W + 0.5 * W * W;
  const double theta = std::sqrt(theta2);
  return Mat3::Identity() + (std::sin(theta) / theta) * W +
         ((1.0 - std::cos(theta)) / theta2) * W * W;
}

Vec3 log_so3(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

double rotation_angle_between(const Mat3& a, const Mat3& b) {
  const double c = std::clamp(((a.transpose() * b).trace() - 1.0) * 0.5, -1.0, 1.0);
  // acos loses precision near zero; use the quaternion form for small angles.
  if (c > 0.999) {
    const Quat q(a.transpose() * b);
    return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
  }
  return std::acos(c);
}

Mat3 nearest_rotation(const Mat3& M) {
  const Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

Mat3 rotation_from_ypr(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitY()) * Eigen::AngleAxisd(pitch, Vec3::UnitX()) *
          Eigen::AngleAxisd(roll, Vec3::UnitZ()))
      .toRotationMatrix();
}

}  // namespace earshot::tracker
