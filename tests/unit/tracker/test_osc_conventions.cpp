// OSC head poses as the trackers in the field send them (SPARTA's and IEM
// SceneRotator's addresses), byte for byte: axis signs checked with rotated
// vectors and against each renderer's own rotation of the scene, single-axis
// state, quaternion order, bundles (nested, malformed), and an outside sender
// (liblo's oscsend) over the loopback. docs/OSC.md is the table these check.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <chrono>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"

extern char** environ;

using namespace earshot::tracker;
using earshot::HeadPose;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
using Bytes = std::vector<std::uint8_t>;

Vec3 ahead(const Quat& q) { return q * Vec3(0, 0, -1); }
Vec3 up(const Quat& q) { return q * Vec3(0, 1, 0); }

/// A SAF / Ambisonics vector (x ahead, y left, z up) in Earshot's axes.
Vec3 from_saf(const Vec3& v) { return {-v.y(), v.z(), -v.x()}; }

Bytes floats(const std::string& path, std::vector<float> args) { return encode_osc_float(path, args); }

/// A decoded head pose in the tracker's Eigen types, for the checks below.
struct Seen {
  Vec3 position_m = Vec3::Zero();
  Quat orientation = Quat::Identity();
};
Seen seen(const HeadPose& p) { return {to_eigen(p.position), to_eigen(p.orientation)}; }

/// The pose a datagram gives; fails the test when it gives none.
Seen pose_of(OscPoseDecoder& d, const Bytes& b) {
  std::string why;
  const auto m = d.decode(b, &why);
  EXPECT_TRUE(m && m->pose) << why;
  return m && m->pose ? seen(*m->pose) : Seen{};
}

std::string reason_of(OscPoseDecoder& d, const Bytes& b) {
  std::string why;
  const auto m = d.decode(b, &why);
  EXPECT_FALSE(m) << "decoded, expected a drop";
  return why;
}

/// Some world directions to rotate (SAF axes), not on any axis.
std::vector<Vec3> directions() {
  return {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.6, -0.3, 0.74).normalized(), Vec3(-0.2, 0.9, -0.4).normalized()};
}

}  // namespace

// SPARTA / SAF: the angles are the head's, about SAF's axes by the right-hand
// rule: yaw +30 turns the head left, pitch + nods it down, roll + tilts it
// toward the right shoulder.
TEST(OscSparta, YprTurnsTheHeadBySafsRightHandRule) {
  OscPoseDecoder d;
  Quat q = pose_of(d, floats("/ypr", {30, 0, 0})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(-std::sin(30 * kDeg), 0, -std::cos(30 * kDeg)), 1e-6)) << ahead(q).transpose();
  q = pose_of(d, floats("/ypr", {0, 20, 0})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(0, -std::sin(20 * kDeg), -std::cos(20 * kDeg)), 1e-6)) << ahead(q).transpose();
  q = pose_of(d, floats("/ypr", {0, 0, 15})).orientation;
  EXPECT_TRUE(up(q).isApprox(Vec3(std::sin(15 * kDeg), std::cos(15 * kDeg), 0), 1e-6)) << up(q).transpose();
}

// What SAF's binauraliser does with (yaw, pitch, roll): it turns every source
// direction by R = Rx(roll) Ry(pitch) Rz(yaw) built from its frame-rotation
// matrices (getRx/getRy/getRz in saf_utility_geometry.c, the transposes of the
// active ones). Earshot must hear each source where SAF puts it.
TEST(OscSparta, HeadRelativeDirectionsMatchSafsSceneRotation) {
  OscPoseDecoder d;
  const double yaw = 35, pitch = -20, roll = 12;
  const Quat q = pose_of(d, floats("/ypr", {float(yaw), float(pitch), float(roll)})).orientation;
  using A = Eigen::AngleAxisd;
  const Eigen::Matrix3d active =
      (A(yaw * kDeg, Vec3::UnitZ()) * A(pitch * kDeg, Vec3::UnitY()) * A(roll * kDeg, Vec3::UnitX())).toRotationMatrix();
  const Eigen::Matrix3d saf = active.transpose();  // Rx^T(roll) Ry^T(pitch) Rz^T(yaw)
  for (const Vec3& dir : directions())
    EXPECT_TRUE((q.inverse() * from_saf(dir)).isApprox(from_saf(saf * dir), 1e-5)) << dir.transpose();
}

TEST(OscSparta, SingleAxisMessagesKeepTheOtherAngles) {
  OscPoseDecoder d;
  (void)pose_of(d, floats("/ypr", {10, 20, 30}));
  OscPoseDecoder fresh;
  Quat q = pose_of(d, floats("/yaw", {40})).orientation;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {40, 20, 30})).orientation), 0.0, 1e-6);
  q = pose_of(d, floats("/pitch", {-5})).orientation;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {40, -5, 30})).orientation), 0.0, 1e-6);
  q = pose_of(d, floats("/roll", {0})).orientation;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {40, -5, 0})).orientation), 0.0, 1e-6);
  // A lone /yaw on a fresh decoder starts from level.
  OscPoseDecoder lone;
  q = pose_of(lone, floats("/yaw", {90})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(-1, 0, 0), 1e-6));
}

// /quaternion is w x y z, the head's orientation about SAF's axes, the same
// rotation SAF's euler2Quaternion makes of yaw, pitch, roll.
TEST(OscSparta, QuaternionIsWxyzAndAgreesWithYpr) {
  OscPoseDecoder d;
  const double h = std::sqrt(0.5);
  Quat q = pose_of(d, floats("/quaternion", {float(h), 0, 0, float(h)})).orientation;  // 90 degrees about z (up)
  EXPECT_TRUE(ahead(q).isApprox(Vec3(-1, 0, 0), 1e-6)) << "w first: a turn to the left; " << ahead(q).transpose();

  const double yaw = -50, pitch = 25, roll = 10;
  const double cy = std::cos(yaw * kDeg / 2), sy = std::sin(yaw * kDeg / 2), cp = std::cos(pitch * kDeg / 2),
               sp = std::sin(pitch * kDeg / 2), cr = std::cos(roll * kDeg / 2), sr = std::sin(roll * kDeg / 2);
  const float w = float(cy * cr * cp + sy * sr * sp), x = float(cy * sr * cp - sy * cr * sp),
              y = float(cy * cr * sp + sy * sr * cp), z = float(sy * cr * cp - cy * sr * sp);
  q = pose_of(d, floats("/quaternion", {w, x, y, z})).orientation;
  OscPoseDecoder fresh;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {float(yaw), float(pitch), float(roll)})).orientation),
              0.0, 1e-6);
  // The quaternion also sets the angles a later single-axis message keeps.
  q = pose_of(d, floats("/yaw", {0})).orientation;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {0, float(pitch), float(roll)})).orientation), 0.0, 1e-5);
}

TEST(OscSparta, XyzIsAPositionInSafAxesAndOrientationIsKept) {
  OscPoseDecoder d;
  (void)pose_of(d, floats("/ypr", {90, 0, 0}));
  Seen p = pose_of(d, floats("/xyz", {1.0f, 0.5f, 0.25f}));  // 1 m ahead, 0.5 m left, 0.25 m up
  EXPECT_TRUE(p.position_m.isApprox(Vec3(-0.5, 0.25, -1.0), 1e-6)) << p.position_m.transpose();
  EXPECT_TRUE(ahead(p.orientation).isApprox(Vec3(-1, 0, 0), 1e-6));
  p = pose_of(d, floats("/yaw", {0}));  // the position stays
  EXPECT_TRUE(p.position_m.isApprox(Vec3(-0.5, 0.25, -1.0), 1e-6));
  EXPECT_TRUE(ahead(p.orientation).isApprox(Vec3(0, 0, -1), 1e-6));
  EXPECT_NE(reason_of(d, floats("/xyz", {20, 0, 0})).find("beyond"), std::string::npos);
}

// IEM SceneRotator: the values rotate the SCENE (extrinsic yaw, pitch, roll
// about x ahead, y left, z up); the head that hears that is the inverse, so
// yaw +30 is the head turned 30 degrees to the RIGHT.
TEST(OscSceneRotator, YprIsTheScenesRotationSoTheHeadTurnsTheOtherWay) {
  OscPoseDecoder d;
  Quat q = pose_of(d, floats("/SceneRotator/ypr", {30, 0, 0})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(std::sin(30 * kDeg), 0, -std::cos(30 * kDeg)), 1e-6)) << ahead(q).transpose();
  q = pose_of(d, floats("/SceneRotator/ypr", {0, 20, 0})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(0, std::sin(20 * kDeg), -std::cos(20 * kDeg)), 1e-6)) << ahead(q).transpose();
  q = pose_of(d, floats("/SceneRotator/ypr", {0, 0, 15})).orientation;
  EXPECT_TRUE(up(q).isApprox(Vec3(-std::sin(15 * kDeg), std::cos(15 * kDeg), 0), 1e-6)) << up(q).transpose();
}

// SceneRotator's matrix for its default sequence (yaw -> pitch -> roll,
// extrinsic) is Rx(roll) Ry(pitch) Rz(yaw) applied to the scene
// (calcRotationMatrix); Earshot must hear each source where it puts it.
TEST(OscSceneRotator, HeadRelativeDirectionsMatchTheRotatedScene) {
  OscPoseDecoder d;
  const double yaw = -70, pitch = 15, roll = -25;
  const Quat q = pose_of(d, floats("/SceneRotator/ypr", {float(yaw), float(pitch), float(roll)})).orientation;
  using A = Eigen::AngleAxisd;
  const Eigen::Matrix3d scene =
      (A(roll * kDeg, Vec3::UnitX()) * A(pitch * kDeg, Vec3::UnitY()) * A(yaw * kDeg, Vec3::UnitZ())).toRotationMatrix();
  for (const Vec3& dir : directions())
    EXPECT_TRUE((q.inverse() * from_saf(dir)).isApprox(from_saf(scene * dir), 1e-5)) << dir.transpose();
}

// /SceneRotator/quaternions is w x y z of the scene's rotation, the quaternion
// SceneRotator itself derives from its angles (updateQuaternions:
// qx(roll) qy(pitch) qz(yaw)); single components wait for a unit quaternion.
TEST(OscSceneRotator, QuaternionsAreWxyzOfTheSceneRotation) {
  const double yaw = 40, pitch = -10, roll = 20;
  const double wa = std::cos(yaw * kDeg / 2), za = std::sin(yaw * kDeg / 2), wb = std::cos(pitch * kDeg / 2),
               yb = std::sin(pitch * kDeg / 2), wc = std::cos(roll * kDeg / 2), xc = std::sin(roll * kDeg / 2);
  const float qw = float(wc * wb * wa - xc * yb * za), qx = float(wc * yb * za + xc * wb * wa),
              qy = float(wc * yb * wa - xc * wb * za), qz = float(wc * wb * za + xc * yb * wa);
  OscPoseDecoder ref;
  const Quat want = pose_of(ref, floats("/SceneRotator/ypr", {float(yaw), float(pitch), float(roll)})).orientation;

  OscPoseDecoder d;
  EXPECT_NEAR(pose_of(d, floats("/SceneRotator/quaternions", {qw, qx, qy, qz})).orientation.angularDistance(want), 0.0,
              1e-6);
  // One component at a time: dropped (not unit yet) until all four are in.
  OscPoseDecoder s;
  (void)pose_of(s, floats("/SceneRotator/yaw", {90}));
  EXPECT_NE(reason_of(s, floats("/SceneRotator/qw", {qw})).find("waiting"), std::string::npos);
  EXPECT_NE(reason_of(s, floats("/SceneRotator/qx", {qx})).find("waiting"), std::string::npos);
  (void)s.decode(floats("/SceneRotator/qy", {qy}), nullptr);  // may or may not be unit by chance
  EXPECT_NEAR(pose_of(s, floats("/SceneRotator/qz", {qz})).orientation.angularDistance(want), 0.0, 1e-6);
  // And the angles follow: a later /roll keeps this yaw and pitch.
  OscPoseDecoder fresh;
  EXPECT_NEAR(pose_of(s, floats("/SceneRotator/roll", {0})).orientation.angularDistance(
                  pose_of(fresh, floats("/SceneRotator/ypr", {float(yaw), float(pitch), 0})).orientation),
              0.0, 1e-5);
}

// SceneRotator normalises the quaternion it is sent (updateEuler) after its
// parameters clamp each component to -1..1 (OSCParameterInterface::setValue):
// so does Earshot. Only a quaternion with no direction is refused.
TEST(OscSceneRotator, QuaternionsAreClampedThenNormalisedAsIemDoes) {
  OscPoseDecoder d, ref;
  // 2 0 0 0 clamps to 1 0 0 0: straight ahead.
  EXPECT_NEAR(pose_of(d, floats("/SceneRotator/quaternions", {2, 0, 0, 0})).orientation.angularDistance(Quat::Identity()),
              0.0, 1e-9);
  // Half length, the scene turned 90 degrees left about up: the head turned right.
  const Quat q = pose_of(d, floats("/SceneRotator/quaternions", {0.5f, 0, 0, 0.5f})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(1, 0, 0), 1e-6)) << ahead(q).transpose();
  // 2 0.5 0 0 clamps to 1 0.5 0 0 before it is normalised: IEM's rotation, not (2 0.5 0 0)'s.
  const Quat clamped = pose_of(d, floats("/SceneRotator/quaternions", {2, 0.5f, 0, 0})).orientation;
  const Quat iem = pose_of(ref, floats("/SceneRotator/quaternions", {float(1 / std::sqrt(1.25)), float(0.5 / std::sqrt(1.25)), 0, 0})).orientation;
  EXPECT_NEAR(clamped.angularDistance(iem), 0.0, 1e-6);
  EXPECT_NE(reason_of(d, floats("/SceneRotator/quaternions", {0, 0, 0, 0})).find("no direction"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/SceneRotator/quaternions", {0, 0, 1e-5f, 0})).find("no direction"), std::string::npos);
  // A component beyond 1 is clamped too, and counts once the four are near unit.
  OscPoseDecoder s;
  (void)pose_of(s, floats("/SceneRotator/quaternions", {0, 1, 0, 0}));
  EXPECT_NEAR(pose_of(s, floats("/SceneRotator/qx", {1.5f})).orientation.angularDistance(
                  pose_of(ref, floats("/SceneRotator/quaternions", {0, 1, 0, 0})).orientation),
              0.0, 1e-9);
}

// Out-of-range angles, as each receiver takes them: SceneRotator's yaw,
// pitch and roll parameters are -180..180 and clamp what is beyond; SAF
// (SPARTA) and Earshot take any angle, periodic.
TEST(OscAngles, SceneRotatorClampsSpartaAndEarshotWrap) {
  OscPoseDecoder d, ref;
  EXPECT_NEAR(pose_of(d, floats("/SceneRotator/ypr", {190, 0, 0})).orientation.angularDistance(
                  pose_of(ref, floats("/SceneRotator/ypr", {180, 0, 0})).orientation),
              0.0, 1e-6);
  EXPECT_NEAR(pose_of(d, floats("/SceneRotator/pitch", {-500})).orientation.angularDistance(
                  pose_of(ref, floats("/SceneRotator/ypr", {180, -180, 0})).orientation),
              0.0, 1e-6);
  EXPECT_NEAR(pose_of(d, floats("/ypr", {390, -370, 725})).orientation.angularDistance(
                  pose_of(ref, floats("/ypr", {30, -10, 5})).orientation),
              0.0, 1e-5);
  EXPECT_NEAR(pose_of(d, floats("/yaw", {1e6f})).orientation.angularDistance(
                  pose_of(ref, floats("/ypr", {float(std::remainder(1e6, 360.0)), -10, 5})).orientation),
              0.0, 1e-5);
  EXPECT_NEAR(pose_of(d, encode_osc("/earshot/ypr", std::vector<double>{400, 0, 0})).orientation.angularDistance(
                  pose_of(ref, floats("/earshot/ypr", {40, 0, 0})).orientation),
              0.0, 1e-9);
  EXPECT_NE(reason_of(d, encode_osc("/earshot/ypr", std::vector<double>{INFINITY, 0, 0})).find("not finite"),
            std::string::npos);
}

// IEM matches its addresses whatever their case (equalsIgnoreCase): so does
// Earshot, for every address it takes.
TEST(OscAddresses, MatchInAnyCase) {
  for (const auto& [a, b] : std::vector<std::pair<std::string, std::string>>{
           {"/SCENEROTATOR/YPR", "/SceneRotator/ypr"}, {"/scenerotator/Quaternions", "/SceneRotator/quaternions"},
           {"/YPR", "/ypr"}, {"/Earshot/YPR", "/earshot/ypr"}, {"/Quaternion", "/quaternion"}}) {
    OscPoseDecoder d, ref;
    const std::vector<float> args = b.ends_with("ypr") ? std::vector<float>{30, 10, -5} : std::vector<float>{0.9f, 0.1f, 0.3f, 0.2f};
    EXPECT_NEAR(pose_of(d, floats(a, args)).orientation.angularDistance(pose_of(ref, floats(b, args)).orientation), 0.0, 1e-9)
        << a;
  }
  OscPoseDecoder d;
  std::string why;
  const auto r = d.decode(encode_osc("/EARSHOT/Recenter", {}), &why);
  ASSERT_TRUE(r) << why;
  EXPECT_TRUE(r->recenter);
}

// SPARTA's rotator also takes the quaternion one component at a time
// (/qw /qx /qy /qz: rotator_setQuaternionW...), about SAF's axes like /quaternion.
TEST(OscSparta, RotatorQuaternionComponentsOneAtATime) {
  const double h = std::sqrt(0.5);
  OscPoseDecoder d, ref;
  (void)pose_of(d, floats("/ypr", {0, 0, 0}));
  // 1 0 0 0 to (h 0 0 h): after /qw alone the four are (h 0 0 0), far from unit: wait.
  EXPECT_NE(reason_of(d, floats("/qw", {float(h)})).find("waiting"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/QX", {0})).find("waiting"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/qy", {0})).find("waiting"), std::string::npos);
  const Quat q = pose_of(d, floats("/qz", {float(h)})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(-1, 0, 0), 1e-6)) << "90 degrees about SAF's up: the head left; " << ahead(q).transpose();
  EXPECT_NEAR(q.angularDistance(pose_of(ref, floats("/quaternion", {float(h), 0, 0, float(h)})).orientation), 0.0, 1e-9);
  // A later /pitch keeps this yaw.
  EXPECT_NEAR(pose_of(d, floats("/pitch", {20})).orientation.angularDistance(pose_of(ref, floats("/ypr", {90, 20, 0})).orientation),
              0.0, 1e-5);
}

// SPARTA's 6DoFconv: /quat (the rotator's quaternion), /xyzquat and /xyzypr
// (position in metres, SAF axes, with the orientation).
TEST(OscSixDofConv, QuatXyzquatAndXyzyprAreTheHeadAndItsPosition) {
  const double h = std::sqrt(0.5);
  OscPoseDecoder d, ref;
  Seen p = pose_of(d, floats("/quat", {float(h), 0, 0, float(h)}));
  EXPECT_TRUE(ahead(p.orientation).isApprox(Vec3(-1, 0, 0), 1e-6));
  p = pose_of(d, floats("/xyzquat", {1.0f, 0.5f, 0.25f, float(h), 0, float(h), 0}));  // 1 m ahead, 0.5 left, 0.25 up; pitch 90 about SAF's y
  EXPECT_TRUE(p.position_m.isApprox(Vec3(-0.5, 0.25, -1.0), 1e-6)) << p.position_m.transpose();
  EXPECT_NEAR(p.orientation.angularDistance(pose_of(ref, floats("/quaternion", {float(h), 0, float(h), 0})).orientation), 0.0, 1e-6);
  EXPECT_TRUE(ahead(p.orientation).isApprox(Vec3(0, -1, 0), 1e-6)) << "SAF's pitch + nods down: " << ahead(p.orientation).transpose();
  p = pose_of(d, floats("/xyzypr", {0, -0.2f, 0, 30, 0, 0}));  // 0.2 m right, yaw 30 left
  EXPECT_TRUE(p.position_m.isApprox(Vec3(0.2, 0, 0), 1e-6)) << p.position_m.transpose();
  EXPECT_NEAR(p.orientation.angularDistance(pose_of(ref, floats("/ypr", {30, 0, 0})).orientation), 0.0, 1e-6);
  // The position stays for the rotator's messages that follow.
  EXPECT_TRUE(pose_of(d, floats("/yaw", {0})).position_m.isApprox(Vec3(0.2, 0, 0), 1e-6));
  EXPECT_NE(reason_of(d, floats("/xyzypr", {30, 0, 0, 0, 0, 0})).find("beyond"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/xyzquat", {0, 0, 0, 1, 0})).find("expected 7 numbers"), std::string::npos);
}

// The senders' side (tracker/send) of each convention is the inverse of the
// decoder's: a head in, the numbers out, the decoder gives the head back,
// for every sign.
TEST(OscConventions, EncodingIsTheInverseOfDecoding) {
  for (const auto& ypr : std::vector<std::array<double, 3>>{{30, 0, 0}, {0, 20, 0}, {0, 0, -15}, {-120, 40, 70}, {170, -80, 5}}) {
    const Quat head = to_eigen(earshot::quat_from_ypr(ypr[0] * kDeg, ypr[1] * kDeg, ypr[2] * kDeg));
    OscPoseDecoder d;
    const auto sp = sparta_ypr(head);
    EXPECT_NEAR(pose_of(d, encode_osc("/ypr", sp)).orientation.angularDistance(head), 0.0, 1e-9);
    const auto sq = sparta_quaternion(head);
    EXPECT_NEAR(pose_of(d, encode_osc("/quaternion", sq)).orientation.angularDistance(head), 0.0, 1e-9);
    const auto iy = scene_rotator_ypr(head);
    EXPECT_NEAR(pose_of(d, encode_osc("/SceneRotator/ypr", iy)).orientation.angularDistance(head), 0.0, 1e-9);
    const auto iq = scene_rotator_quaternions(head);
    EXPECT_NEAR(pose_of(d, encode_osc("/SceneRotator/quaternions", iq)).orientation.angularDistance(head), 0.0, 1e-9);
  }
  // The signs, one by one: Earshot's yaw +30 (left) is SPARTA's yaw +30 and
  // SceneRotator's -30; pitch +20 (up) is SPARTA's -20 and SceneRotator's +20;
  // roll +15 (right shoulder) is SPARTA's +15 and SceneRotator's -15.
  auto head = [](double y, double p, double r) { return to_eigen(earshot::quat_from_ypr(y * kDeg, p * kDeg, r * kDeg)); };
  EXPECT_NEAR(sparta_ypr(head(30, 0, 0))[0], 30, 1e-9);
  EXPECT_NEAR(sparta_ypr(head(0, 20, 0))[1], -20, 1e-9);
  EXPECT_NEAR(sparta_ypr(head(0, 0, 15))[2], 15, 1e-9);
  EXPECT_NEAR(scene_rotator_ypr(head(30, 0, 0))[0], -30, 1e-9);
  EXPECT_NEAR(scene_rotator_ypr(head(0, 20, 0))[1], 20, 1e-9);
  EXPECT_NEAR(scene_rotator_ypr(head(0, 0, 15))[2], -15, 1e-9);
  EXPECT_TRUE(earshot_to_saf(Vec3(0.1, 0.2, -0.3)).isApprox(Vec3(0.3, -0.1, 0.2)));  // ahead 0.3, right 0.1, up 0.2
  EXPECT_TRUE(saf_to_earshot(0.3, -0.1, 0.2).isApprox(Vec3(0.1, 0.2, -0.3)));
}

// write_osc_floats is what the senders put on the wire: liblo reads it back
// (the same bytes as liblo's own float32 message), and bad addresses or a
// short buffer write nothing.
TEST(OscConventions, WriteOscFloatsIsLiblosFloat32Message) {
  std::array<std::uint8_t, 128> buf{};
  const std::vector<float> args{1.5f, -2.25f, 90.0f};
  for (const std::string address : {"/ypr", "/SceneRotator/ypr", "/abc", "/abcdefg"}) {
    const std::size_t n = write_osc_floats(buf, address, args);
    EXPECT_EQ(Bytes(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)), floats(address, args)) << address;
  }
  EXPECT_EQ(write_osc_floats(buf, "ypr", args), 0u);
  EXPECT_EQ(write_osc_floats(buf, "", args), 0u);
  EXPECT_EQ(write_osc_floats(std::span(buf.data(), 15), "/ypr", args), 0u);
}

TEST(OscSceneRotator, SingleAxisMessagesKeepTheOtherAngles) {
  OscPoseDecoder d, fresh;
  (void)pose_of(d, floats("/SceneRotator/ypr", {10, 20, 30}));
  EXPECT_NEAR(pose_of(d, floats("/SceneRotator/pitch", {-40})).orientation.angularDistance(
                  pose_of(fresh, floats("/SceneRotator/ypr", {10, -40, 30})).orientation),
              0.0, 1e-6);
  // The two conventions keep separate state.
  EXPECT_NEAR(pose_of(d, floats("/yaw", {0})).orientation.angularDistance(Quat::Identity()), 0.0, 1e-9);
  EXPECT_NE(reason_of(d, floats("/SceneRotator/zoom", {1})).find("not one of ours"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/SceneRotator/ypr", {1, 2})).find("expected 3 numbers"), std::string::npos);
  EXPECT_NE(reason_of(d, floats("/yaw", {NAN})).find("not finite"), std::string::npos);
}

TEST(OscEarshot, OwnAddressesAreUnchangedAndStateless) {
  OscPoseDecoder d;
  (void)pose_of(d, floats("/ypr", {45, 0, 0}));
  const Quat q = pose_of(d, floats("/earshot/ypr", {90, 0, 0})).orientation;
  EXPECT_TRUE(ahead(q).isApprox(Vec3(-1, 0, 0), 1e-6));
  const Seen p = pose_of(d, floats("/earshot/pose/ypr", {0.1f, 0.2f, -0.3f, 0, 0, 0}));
  EXPECT_TRUE(p.position_m.isApprox(Vec3(0.1, 0.2, -0.3), 1e-6));
}

// ---- Bundles --------------------------------------------------------------

TEST(OscBundle, TheLastPoseWinsAndARecenterAnywhereCounts) {
  OscPoseDecoder d;
  const std::vector<Bytes> elements{floats("/ypr", {10, 0, 0}), encode_osc("/earshot/recenter", {}),
                                    floats("/ypr", {20, 0, 0})};
  std::string why;
  const auto m = d.decode(encode_osc_bundle(elements), &why);
  ASSERT_TRUE(m && m->pose) << why;
  EXPECT_TRUE(m->recenter);
  EXPECT_TRUE(ahead(to_eigen(m->pose->orientation)).isApprox(Vec3(-std::sin(20 * kDeg), 0, -std::cos(20 * kDeg)), 1e-6));
  // A recenter alone in a bundle is a recenter.
  const auto r = d.decode(encode_osc_bundle(std::vector<Bytes>{encode_osc("/earshot/recenter", {})}), &why);
  ASSERT_TRUE(r) << why;
  EXPECT_TRUE(r->recenter);
  EXPECT_FALSE(r->pose);
}

TEST(OscBundle, NestedBundlesAreDecodedInOrderAndSingleAxisStateFlows) {
  OscPoseDecoder d;
  const Bytes inner = encode_osc_bundle(std::vector<Bytes>{floats("/pitch", {-30})});
  const Bytes outer = encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {90}), inner});
  const Quat q = pose_of(d, outer).orientation;
  OscPoseDecoder fresh;
  EXPECT_NEAR(q.angularDistance(pose_of(fresh, floats("/ypr", {90, -30, 0})).orientation), 0.0, 1e-6);
  // Elements that are not ours are skipped; the rest still count.
  const Bytes mixed = encode_osc_bundle(std::vector<Bytes>{floats("/other", {1}), floats("/yaw", {0})});
  EXPECT_NEAR(pose_of(d, mixed).orientation.angularDistance(pose_of(fresh, floats("/ypr", {0, -30, 0})).orientation),
              0.0, 1e-6);
  EXPECT_NE(reason_of(d, encode_osc_bundle(std::vector<Bytes>{floats("/other", {1})})).find("element 1: OSC address /other"),
            std::string::npos);
}

TEST(OscBundle, MalformedSizesNameTheElementAndChangeNoState) {
  OscPoseDecoder d;
  (void)pose_of(d, floats("/ypr", {30, 0, 0}));
  Bytes b = encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {80}), floats("/yaw", {70})});
  // Element 2's size (at 16 + 4 + 16) claims 4 more bytes than the packet holds.
  const std::size_t second = 16 + 4 + floats("/yaw", {80}).size();
  b[second + 3] = static_cast<std::uint8_t>(b[second + 3] + 4);
  std::string why = reason_of(d, b);
  EXPECT_NE(why.find("element 2"), std::string::npos) << why;
  EXPECT_NE(why.find("beyond the packet"), std::string::npos) << why;
  // Element 1's /yaw 80 was not applied: the state is still yaw 30.
  OscPoseDecoder fresh;
  EXPECT_NEAR(pose_of(d, floats("/pitch", {0})).orientation.angularDistance(pose_of(fresh, floats("/ypr", {30, 0, 0})).orientation),
              0.0, 1e-6);

  b = encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {80})});
  b[16 + 3] = 3;  // not a multiple of 4
  why = reason_of(d, b);
  EXPECT_NE(why.find("element 1: size 3 is not a positive multiple of 4"), std::string::npos) << why;
  b = encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {80})});
  b.resize(18);  // the size field cut off
  EXPECT_NE(reason_of(d, b).find("size field cut off"), std::string::npos);
  b = encode_osc_bundle(std::vector<Bytes>{Bytes{'x', 0, 0, 0}});
  EXPECT_NE(reason_of(d, b).find("neither a message"), std::string::npos);
  EXPECT_NE(reason_of(d, Bytes{'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0}).find("16-byte bundle header"), std::string::npos);
  EXPECT_NE(reason_of(d, encode_osc_bundle(std::vector<Bytes>{})).find("no messages"), std::string::npos);
  // A nested bundle whose element is bad is named by its path.
  Bytes inner = encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {1})});
  inner[16 + 3] = 200;
  why = reason_of(d, encode_osc_bundle(std::vector<Bytes>{floats("/yaw", {1}), inner}));
  EXPECT_NE(why.find("element 2.1"), std::string::npos) << why;
}

TEST(OscBundle, DepthAndElementCountAreBounded) {
  OscPoseDecoder d;
  Bytes b = floats("/yaw", {1});
  for (int level = 1; level <= kOscMaxBundleDepth; ++level) b = encode_osc_bundle(std::vector<Bytes>{b});
  EXPECT_TRUE(d.decode(b, nullptr)) << "8 levels are allowed";
  b = encode_osc_bundle(std::vector<Bytes>{b});
  EXPECT_NE(reason_of(d, b).find("nested deeper than 8"), std::string::npos);

  std::vector<Bytes> many(kOscMaxBundleElements, floats("/yaw", {1}));
  EXPECT_TRUE(d.decode(encode_osc_bundle(many), nullptr));
  many.push_back(floats("/yaw", {1}));
  EXPECT_NE(reason_of(d, encode_osc_bundle(many)).find("more than 64 elements"), std::string::npos);
}

// A bundle with a pose and a recenter: the source delivers the pose, then the
// recenter, as two events.
TEST(OscBundle, TheSourceDeliversThePoseThenTheRecenter) {
  UdpPoseSource src("osc", 0, std::string("127.0.0.1"), OscPoseDecoder::packet_decoder());
  send_udp_loopback(src.port(), encode_osc_bundle(std::vector<Bytes>{encode_osc("/earshot/recenter", {}),
                                                                       floats("/earshot/ypr", {0, 0, 0})}));
  std::vector<std::string> seen;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (seen.size() < 2 && std::chrono::steady_clock::now() < deadline) {
    const auto e = src.next(std::chrono::milliseconds(100));
    if (std::holds_alternative<HeadPose>(e)) seen.push_back("pose");
    else if (const auto* n = std::get_if<SourceNote>(&e); n && n->kind == SourceNote::Kind::recenter) seen.push_back("recenter");
  }
  EXPECT_EQ(seen, (std::vector<std::string>{"pose", "recenter"}));
}

// ---- An outside sender: liblo's oscsend --------------------------------------

namespace {

std::string oscsend_path() {
  for (const char* p : {"/usr/bin/oscsend", "/usr/local/bin/oscsend"})
    if (::access(p, X_OK) == 0) return p;
  return {};
}

/// Runs oscsend with these arguments; its exit status.
int oscsend(const std::vector<std::string>& args) {
  std::vector<std::string> all{oscsend_path()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (::posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The first pose the source delivers within a few seconds.
std::optional<Seen> next_pose(UdpPoseSource& src) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < deadline) {
    const SourceEvent e = src.next(std::chrono::milliseconds(100));
    if (const auto* p = std::get_if<HeadPose>(&e)) return seen(*p);
  }
  return std::nullopt;
}

}  // namespace

TEST(OscOutsideSender, OscsendDrivesTheHeadInEveryConvention) {
  ASSERT_FALSE(oscsend_path().empty()) << "oscsend not found: install liblo-tools (scripts/install-deps.sh installs it)";
  UdpPoseSource src("osc", 0, std::string("127.0.0.1"), OscPoseDecoder::packet_decoder());
  const std::string port = std::to_string(src.port());
  struct Case {
    std::vector<std::string> args;
    Vec3 want_ahead;
  };
  const double s30 = std::sin(30 * kDeg), c30 = std::cos(30 * kDeg);
  const std::vector<Case> cases{
      {{"/SceneRotator/ypr", "fff", "30", "0", "0"}, Vec3(s30, 0, -c30)},   // the scene turns left: the head right
      {{"/ypr", "fff", "30", "0", "0"}, Vec3(-s30, 0, -c30)},               // SPARTA: the head left
      {{"/pitch", "f", "30"}, Vec3(-s30 * c30, -s30, -c30 * c30)},          // SPARTA: keeps yaw 30, nods down 30
      {{"/yaw", "i", "0"}, Vec3(0, -s30, -c30)},                            // an int32 works too
      {{"/earshot/ypr", "ddd", "-30", "0", "0"}, Vec3(s30, 0, -c30)},       // float64, Earshot's own
      {{"/quaternion", "ffff", "0.7071068", "0", "0", "0.7071068"}, Vec3(-1, 0, 0)},  // SAF: 90 degrees about up
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"127.0.0.1", port};
    args.insert(args.end(), c.args.begin(), c.args.end());
    ASSERT_EQ(oscsend(args), 0) << c.args[0];
    const auto p = next_pose(src);
    ASSERT_TRUE(p) << c.args[0] << ": no pose within 5 s; last error: " << src.last_error();
    EXPECT_TRUE(ahead(p->orientation).isApprox(c.want_ahead, 1e-5))
        << c.args[0] << ": ahead " << ahead(p->orientation).transpose() << ", want " << c.want_ahead.transpose();
  }
  EXPECT_EQ(src.dropped(), 0u) << src.last_error();
}
