#include <gtest/gtest.h>

#include <random>

#include "earshot/tracker/filter/filters.hpp"

using namespace earshot::tracker;

TEST(OneEuro, ReducesJitterOfAStillHead) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  PoseOneEuro f;
  double raw2 = 0, filt2 = 0;
  for (int i = 0; i < 2000; ++i) {
    const Pose noisy{exp_so3(Vec3(n(rng), n(rng), n(rng)) * 0.01), Vec3(n(rng), n(rng), 1000 + n(rng)) * 1.0};
    const Pose out = f.filter(noisy, i * 0.01);
    if (i < 100) continue;
    raw2 += log_so3(noisy.R).squaredNorm();
    filt2 += log_so3(out.R).squaredNorm();
  }
  EXPECT_LT(filt2, 0.2 * raw2);
}

TEST(OneEuro, FollowsAFastTurnWithSmallLag) {
  PoseOneEuro f;
  // 180 deg/s yaw for one second: lag must stay below 30 ms of motion.
  double worst = 0;
  for (int i = 0; i < 100; ++i) {
    const double t = i * 0.01;
    const Pose p{rotation_from_ypr(M_PI * t, 0, 0), Vec3(0, 0, 1000)};
    const Pose out = f.filter(p, t);
    if (i > 30) worst = std::max(worst, rotation_angle_between(out.R, p.R));
  }
  EXPECT_LT(worst, M_PI * 0.03);
}

TEST(MedianFilter, RemovesAnOutlierAndDelaysTwoFrames) {
  MedianPoseFilter m;
  std::vector<Pose> out;
  for (int i = 0; i < 13; ++i) {
    Pose p{Mat3::Identity(), Vec3(i, 0, 1000)};
    if (i == 5) p.t.x() = 500;  // outlier
    out.push_back(m.filter(p));
  }
  for (const auto& p : out) EXPECT_LT(p.t.x(), 13.0);  // the outlier never comes through
  EXPECT_DOUBLE_EQ(out[7].t.x(), 6.0);   // 3,4,(500),6,7
  EXPECT_DOUBLE_EQ(out[12].t.x(), 10.0);  // 8..12: two frames behind the ramp
}

TEST(ConstantVelocity, ExtrapolatesTranslationAndRotation) {
  ConstantVelocity cv;
  cv.observe({rotation_from_ypr(0.0, 0, 0), Vec3(0, 0, 1000)}, 0.0);
  cv.observe({rotation_from_ypr(0.1, 0, 0), Vec3(10, 0, 1000)}, 0.01);
  const auto p = cv.predict(0.03);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->t.x(), 30.0, 1e-9);
  EXPECT_LT(rotation_angle_between(p->R, rotation_from_ypr(0.3, 0, 0)), 1e-9);
}
