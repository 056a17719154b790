// Dense references for the eskf's tests: what its fixed-size block formulas
// must equal.
#pragma once

#include "earshot/tracker/filter/eskf.hpp"

namespace earshot::tracker::fixtures {

/// The pose block of F P F^T + Q over `ahead` seconds, formed densely: F the
/// constant-velocity transition with its rotation block the identity, Q the
/// white acceleration at the filter's current adaptive scales.
inline Mat6 predicted_pose_covariance_reference(const PoseEskf& f, double ahead) {
  const EskfParams p;
  Mat12 F = Mat12::Identity();
  F.block<6, 6>(0, 6) = ahead * Mat6::Identity();
  Mat6 want = (F * f.covariance() * F.transpose()).topLeftCorner<6, 6>();
  const double dt3 = ahead * ahead * ahead / 3.0;
  want.diagonal().head<3>().array() += f.rotation_noise_scale() * p.angular_accel_psd * dt3;
  want.diagonal().tail<3>().array() += f.translation_noise_scale() * p.linear_accel_psd * dt3;
  return want;
}

}  // namespace earshot::tracker::fixtures
