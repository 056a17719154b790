// The eskf's predicted pose covariance (what a gate on the prediction
// needs) equals the pose block of F P F^T + Q formed densely, with F's
// rotation block taken as the identity.
#include <gtest/gtest.h>

#include <random>

#include "earshot/tracker/filter/eskf.hpp"
#include "eskf_reference.hpp"

using namespace earshot::tracker;

TEST(EskfPrediction, PoseCovarianceIsThePoseBlockOfFPFtPlusQ) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  PoseEskf f;
  double t = 0.0;
  for (int k = 0; k < 50; ++k, t += 0.01) {
    const Pose z{exp_so3(Vec3(0.3 * t + 0.002 * n(rng), 0.001 * n(rng), 0.001 * n(rng))), Vec3(100 * t + n(rng), n(rng), 1000 + n(rng))};
    f.update(z, Mat6(Eigen::Matrix<double, 6, 1>(1e-5, 1e-5, 1e-5, 1.0, 1.0, 4.0).asDiagonal()), t);
  }
  const double dt = 0.013, t_last = t - 0.01;
  // q at the filter's current adaptive scales (1 on this slow walk).
  const Mat6 want = fixtures::predicted_pose_covariance_reference(f, dt);
  const auto got = f.predicted_pose_covariance(t_last + dt);
  ASSERT_TRUE(got.has_value());
  EXPECT_LT((*got - want).norm(), 1e-12 * want.norm());
  EXPECT_FALSE(PoseEskf{}.predicted_pose_covariance(1.0).has_value());
}
