// The shared geometry: rotations that are known by heart, the order of a
// composition, slerp's ends and middle, and yaw/pitch/roll both ways,
// including looking straight up and down.
#include "earshot/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "earshot/head_pose.hpp"

namespace earshot {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTol = 1e-12;

void expect_near(const Vec3& a, const Vec3& b, double tol = kTol) {
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

/// Same rotation: q and -q are equal as rotations.
void expect_same_rotation(const Quat& a, const Quat& b, double tol = 1e-9) {
  double d = 0;
  for (std::size_t i = 0; i < 4; ++i) d += a[i] * b[i];
  EXPECT_NEAR(std::abs(d), 1.0, tol) << "a=(" << a[0] << ',' << a[1] << ',' << a[2] << ',' << a[3] << ") b=(" << b[0]
                                     << ',' << b[1] << ',' << b[2] << ',' << b[3] << ')';
}

Quat about(const Vec3& axis, double angle) {
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s};
}

TEST(Geometry, QuarterTurnsRotateTheAxesAsExpected) {
  const Quat z90 = about({0, 0, 1}, kPi / 2);
  expect_near(rotate(z90, {1, 0, 0}), {0, 1, 0});
  expect_near(rotate(z90, {0, 1, 0}), {-1, 0, 0});
  const Quat y90 = about({0, 1, 0}, kPi / 2);
  expect_near(rotate(y90, {0, 0, -1}), {-1, 0, 0});  // a left turn: ahead swings to -x
  expect_near(rotate_inverse(y90, {-1, 0, 0}), {0, 0, -1});
  expect_near(rotate(kIdentityQuat, {0.3, -2, 5}), {0.3, -2, 5});
}

TEST(Geometry, MultiplyAppliesTheRightFactorFirst) {
  const Quat x90 = about({1, 0, 0}, kPi / 2), z90 = about({0, 0, 1}, kPi / 2);
  // x first: +y -> +z; then z leaves +z alone.
  expect_near(rotate(multiply(z90, x90), {0, 1, 0}), {0, 0, 1});
  // z first: +y -> -x; then x leaves -x alone.
  expect_near(rotate(multiply(x90, z90), {0, 1, 0}), {-1, 0, 0});
  expect_same_rotation(multiply(z90, conjugate(z90)), kIdentityQuat);
}

TEST(Geometry, RotateMatchesTheSandwichProduct) {
  const Quat q = *normalised({0.3, -0.5, 0.7, 0.1});
  const Vec3 v{0.2, -1.5, 3.0};
  const Quat r = multiply(multiply(q, Quat{0, v[0], v[1], v[2]}), conjugate(q));
  expect_near(rotate(q, v), {r[1], r[2], r[3]});
}

TEST(Geometry, SlerpHitsItsEndsAndTheMiddleOfTheArc) {
  const Quat a = about({0, 1, 0}, 0.2), b = about({0, 1, 0}, 1.4);
  expect_same_rotation(slerp(a, b, 0.0), a, 1e-12);
  expect_same_rotation(slerp(a, b, 1.0), b, 1e-12);
  expect_same_rotation(slerp(a, b, 0.5), about({0, 1, 0}, 0.8), 1e-12);
  expect_same_rotation(slerp(a, b, 0.25), about({0, 1, 0}, 0.5), 1e-12);
  // -b is the same rotation: the shorter arc still passes through 0.8 rad.
  const Quat nb{-b[0], -b[1], -b[2], -b[3]};
  expect_same_rotation(slerp(a, nb, 0.5), about({0, 1, 0}, 0.8), 1e-12);
  // Nearly equal rotations take the linear branch and stay unit length.
  const Quat m = slerp(a, about({0, 1, 0}, 0.2001), 0.5);
  EXPECT_NEAR(m[0] * m[0] + m[1] * m[1] + m[2] * m[2] + m[3] * m[3], 1.0, 1e-15);
  expect_same_rotation(m, about({0, 1, 0}, 0.20005), 1e-12);
}

TEST(Geometry, YawPitchRollFollowTheStatedConvention) {
  // yaw > 0 turns left, pitch > 0 looks up, roll > 0 tilts up towards +x.
  expect_near(rotate(quat_from_ypr(kPi / 2, 0, 0), {0, 0, -1}), {-1, 0, 0});
  expect_near(rotate(quat_from_ypr(0, kPi / 2, 0), {0, 0, -1}), {0, 1, 0});
  expect_near(rotate(quat_from_ypr(0, 0, kPi / 2), {0, 1, 0}), {1, 0, 0});
  // The order: roll, then pitch, then yaw (each about the world's axes).
  const Quat q = quat_from_ypr(0.4, -0.3, 0.2);
  const Quat by_hand = multiply(about({0, 1, 0}, 0.4), multiply(about({1, 0, 0}, -0.3), about({0, 0, -1}, 0.2)));
  expect_same_rotation(q, by_hand, 1e-14);
}

TEST(Geometry, YawPitchRollRoundTrip) {
  for (double yaw : {-3.0, -1.2, 0.0, 0.5, 2.9})
    for (double pitch : {-1.5, -0.7, 0.0, 0.3, 1.5})
      for (double roll : {-3.0, -0.4, 0.0, 1.1, 3.1}) {
        const YawPitchRoll a = ypr_from_quat(quat_from_ypr(yaw, pitch, roll));
        EXPECT_NEAR(a.yaw, yaw, 1e-9) << yaw << ' ' << pitch << ' ' << roll;
        EXPECT_NEAR(a.pitch, pitch, 1e-9) << yaw << ' ' << pitch << ' ' << roll;
        EXPECT_NEAR(a.roll, roll, 1e-9) << yaw << ' ' << pitch << ' ' << roll;
      }
}

TEST(Geometry, LookingStraightUpOrDownPutsTheTurnInYaw) {
  for (double pitch : {kPi / 2, -kPi / 2})
    for (double roll : {0.0, 0.3}) {
      const Quat q = quat_from_ypr(0.7, pitch, roll);
      const YawPitchRoll a = ypr_from_quat(q);
      EXPECT_NEAR(a.pitch, pitch, 1e-7);
      EXPECT_EQ(a.roll, 0.0);
      // Only yaw -/+ roll is defined: the angles given back are the same rotation.
      expect_same_rotation(quat_from_ypr(a.yaw, a.pitch, a.roll), q, 1e-12);
      EXPECT_NEAR(a.yaw, pitch > 0 ? 0.7 + roll : 0.7 - roll, 1e-7);  // up: roll turns about +y too
    }
}

TEST(Geometry, AtUpGivesTheRotationOfTheRestFrame) {
  const auto q = quat_from_at_up({-1, 0, 0}, {0, 1, 0});
  ASSERT_TRUE(q);
  expect_same_rotation(*q, quat_from_ypr(kPi / 2, 0, 0), 1e-14);
  EXPECT_FALSE(quat_from_at_up({0, 1, 0}, {0, 2, 0}));  // parallel
  EXPECT_FALSE(quat_from_at_up({0, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(normalised({0, 0, 0, 0}));
  EXPECT_FALSE(normalised({NAN, 0, 0, 1}));
}

TEST(PoseState, NamesRoundTrip) {
  for (auto s : {PoseState::searching, PoseState::tracking, PoseState::predicted, PoseState::lost})
    EXPECT_EQ(pose_state_from_name(pose_state_name(s)), s);
  EXPECT_EQ(pose_state_name(PoseState::predicted), "predicted");
  EXPECT_FALSE(pose_state_from_name("Tracking"));
  EXPECT_FALSE(pose_state_from_name(""));
}

}  // namespace
}  // namespace earshot
