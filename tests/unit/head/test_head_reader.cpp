// The head as every host reads it (head/): the slot read once per block, the
// prediction to when the block is heard, the composition with the host's
// listener, the tracker started from a spec; and the preload shim's use of
// them (its listener is predicted too).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <thread>

#include "earshot/errors.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/head/tracked_head.hpp"
#include "shim_listener.hpp"

namespace earshot::head {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// A head turning left (about +y) at `deg_per_s`, yawed `yaw_deg`, at steady time `t`.
HeadPose turning(double yaw_deg, double deg_per_s, double t) {
  HeadPose p;
  p.orientation = quat_from_ypr(yaw_deg * kDeg, 0, 0);
  p.angular_velocity = {0, deg_per_s * kDeg, 0};
  p.velocity = {0.1, 0, 0};
  p.state = PoseState::tracking;
  p.steady_s = t;
  p.t = t;
  return p;
}

double yaw_deg(const HeadPose& p) { return ypr_from_quat(p.orientation).yaw / kDeg; }

TEST(HeadReader, PredictsToWhenTheBlockIsHeard) {
  PoseSlot slot;
  ASSERT_TRUE(slot.publish(turning(10, 100, 50.0)));
  HeadReader r;
  // Read 5 ms after the pose, heard 20 ms later: 25 ms of turning at 100 deg/s.
  const HeadPose p = r.read_at(slot, {.predict = true, .lead_s = 0.020}, 50.005);
  EXPECT_NEAR(yaw_deg(p), 12.5, 1e-9);
  EXPECT_NEAR(p.position[0], 0.1 * 0.025, 1e-12);
  EXPECT_NEAR(yaw_deg(r.last()), 10.0, 1e-9);  // what the slot held
  const HeadPose q = r.read_at(slot, {.predict = false, .lead_s = 0.020}, 50.005);
  EXPECT_NEAR(yaw_deg(q), 10.0, 1e-9);
}

TEST(HeadReader, PredictsNoFurtherThanTheLimitAndNotWhileBridging) {
  PoseSlot slot;
  ASSERT_TRUE(slot.publish(turning(0, 100, 1.0)));
  HeadReader r;
  const HeadPose far = r.read_at(slot, {.predict = true, .lead_s = 1.0}, 1.0);
  EXPECT_NEAR(yaw_deg(far), 100 * kMaxHeadPredictionS, 1e-9);
  HeadPose bridging = turning(0, 100, 2.0);
  bridging.state = PoseState::predicted;  // the tracker is carrying it through a gap already
  ASSERT_TRUE(slot.publish(bridging));
  EXPECT_NEAR(yaw_deg(r.read_at(slot, {.predict = true, .lead_s = 0.05}, 2.0)), 0.0, 1e-12);
}

TEST(HeadReader, KeepsTheLastPoseWhileTheSlotHasNothingNew) {
  PoseSlot slot;
  HeadReader r;
  EXPECT_NEAR(yaw_deg(r.read_at(slot, {.predict = true, .lead_s = 0.01}, 0.0)), 0.0, 1e-12);  // nothing yet
  ASSERT_TRUE(slot.publish(turning(30, 0, 1.0)));
  EXPECT_NEAR(yaw_deg(r.read_at(slot, {}, 1.0)), 30.0, 1e-9);
  r.reset();
  EXPECT_NEAR(yaw_deg(r.last()), 0.0, 1e-12);
}

TEST(Compose, PlacesTheHeadOnTheHostsListener) {
  HeadPose listener;
  listener.position = {1, 2, 3};
  listener.orientation = quat_from_ypr(90 * kDeg, 0, 0);  // turned left: its right is world -z
  HeadPose head;
  head.position = {0.1, 0, 0};  // 10 cm to the listener's right
  head.orientation = quat_from_ypr(10 * kDeg, 0, 0);
  const HeadPose out = compose(listener, head);
  EXPECT_NEAR(out.position[0], 1.0, 1e-12);
  EXPECT_NEAR(out.position[1], 2.0, 1e-12);
  EXPECT_NEAR(out.position[2], 3.0 - 0.1, 1e-12);
  EXPECT_NEAR(yaw_deg(out), 100.0, 1e-9);
  head.position[0] = std::nan("");
  const HeadPose kept = compose(listener, head);
  EXPECT_EQ(kept.position, listener.position);
  EXPECT_EQ(kept.orientation, listener.orientation);
}

TEST(TrackedHead, PublishesTheSimulatedHeadAndNamesTheFieldOfABadSpec) {
  PoseSlot slot;
  {
    TrackedHead head("sim", slot);
    EXPECT_EQ(head.spec(), "sim");
    EXPECT_EQ(head.camera_width(), 1024);  // the Wii camera the simulator sees through
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (slot.load().sequence < 5 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_GE(slot.load().sequence, 5u);
  }
  try {
    TrackedHead bad("nonsense", slot, {}, "--tracker");
    FAIL() << "a bad spec started";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--tracker"), std::string::npos) << e.what();
  }
}

TEST(ShimListener, TheProgramsListenerHearsThePredictedHead) {
  HeadPose program;
  program.position = {0, 1.5, 0};
  const HeadPose tracked = turning(0, 200, 10.0);
  const preload::ShimListener now = preload::shim_listener(program, tracked, 0.0, 10.0);
  const preload::ShimListener ahead = preload::shim_listener(program, tracked, 0.030, 10.0);
  EXPECT_NEAR(yaw_deg(now.head), 0.0, 1e-9);
  EXPECT_NEAR(yaw_deg(ahead.head), 6.0, 1e-9);  // 30 ms at 200 deg/s
  // "at" turned 6 degrees left (towards -x) of straight ahead (-z).
  EXPECT_NEAR(std::atan2(-ahead.orientation[0], -ahead.orientation[2]) / kDeg, 6.0, 1e-4);
  EXPECT_NEAR(ahead.position[1], 1.5f, 1e-6);
}

}  // namespace
}  // namespace earshot::head
