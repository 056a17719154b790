#include "earshot/tracker/motion_reach.hpp"

#include <algorithm>
#include <cmath>

namespace earshot::tracker {

double ou_displacement_variance(double q, double tau, double dt) {
  const double x = dt / tau;
  return 0.5 * q * tau * tau * tau * (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x));
}

double pose_mahalanobis2(const Pose& p, const Pose& pred, const Mat6& spread) {
  Eigen::Matrix<double, 6, 1> nu;
  nu.head<3>() = log_so3(p.R * pred.R.transpose());
  nu.tail<3>() = p.t - pred.t;
  return nu.dot(spread.ldlt().solve(nu));
}

double carried_mahalanobis2(const EskfStep& from, const EskfParams& q, double t, const Pose& p, const Mat6& p_cov) {
  const double dt = std::max(0.0, t - from.t);
  // The OU velocity's mean decays: the pose moves w tau (1 - e^(-dt/tau)).
  const double kr = kHeadRotationTauS * (1.0 - std::exp(-dt / kHeadRotationTauS));
  const double kt = kHeadTranslationTauS * (1.0 - std::exp(-dt / kHeadTranslationTauS));
  const Pose pred{exp_so3(from.w_upd * kr) * from.pose_upd.R, from.pose_upd.t + from.v_upd * kt};
  Eigen::Matrix<double, 6, 12> A = Eigen::Matrix<double, 6, 12>::Zero();
  A.leftCols<6>().setIdentity();
  A.block<3, 3>(0, 6) = kr * Mat3::Identity();
  A.block<3, 3>(3, 9) = kt * Mat3::Identity();
  Mat6 spread = A * from.P_upd * A.transpose() + p_cov;
  spread.diagonal().head<3>().array() +=
      kMaxManoeuvreScale * ou_displacement_variance(q.angular_accel_psd, kHeadRotationTauS, dt);
  spread.diagonal().tail<3>().array() +=
      kMaxManoeuvreScale * ou_displacement_variance(q.linear_accel_psd, kHeadTranslationTauS, dt);
  return pose_mahalanobis2(p, pred, spread);
}

}  // namespace earshot::tracker
