#include "earshot/tracker/filter/motion_reach.hpp"

namespace earshot::tracker {

OuMotion head_motion(const EskfParams& q, double scale) {
  return {scale * q.angular_accel_psd, scale * q.linear_accel_psd, kHeadRotationTauS, kHeadTranslationTauS};
}

double pose_mahalanobis2(const Pose& p, const Pose& pred, const Mat6& spread) {
  Eigen::Matrix<double, 6, 1> nu;
  nu.head<3>() = log_so3(p.R * pred.R.transpose());
  nu.tail<3>() = p.t - pred.t;
  return nu.dot(spread.ldlt().solve(nu));
}

double carried_mahalanobis2(const EskfStep& from, const EskfParams& q, double t, const Pose& p, const Mat6& p_cov) {
  const CarriedPose c = carry_ou(from, t, head_motion(q, kMaxManoeuvreScale));
  return pose_mahalanobis2(p, c.pose, c.spread + p_cov);
}

}  // namespace earshot::tracker
