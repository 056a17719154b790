#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/sim/head_trace.hpp"
#include "earshot/tracker/sim/simulator.hpp"

using namespace earshot::tracker;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

/// An orientation-only trace (x forward, y left, z up) written here: a head
/// that holds heading h0 for a while, then turns its yaw by `turn` deg about
/// the world's z at a steady rate and holds there.
std::string viewer_trace(double h0_deg, double turn_deg, double hold_s = 2.0) {
  std::ostringstream s;
  s << "t_s,qw,qx,qy,qz\n";
  for (int i = 0; i <= 300; ++i) {
    const double t = 10.0 + 0.017 * i;  // source time, not from zero
    const double u = std::clamp((0.017 * i - hold_s) / 1.0, 0.0, 1.0);
    const double yaw = (h0_deg + u * turn_deg) * kDeg;
    s << t << "," << std::cos(yaw / 2) << ",0,0," << std::sin(yaw / 2) << "\n";
  }
  return s.str();
}
}  // namespace

TEST(HeadTrace, TheMostHeldHeadingFacesTheCamera) {
  std::istringstream in(viewer_trace(70.0, 0.0));
  const HeadTrace h = HeadTrace::parse(in, "test");
  EXPECT_NEAR(h.front_rad(), 70.0 * kDeg, 1.0 * kDeg);
  EXPECT_NEAR(h.duration(), 300 * 0.017, 1e-9);
  const Pose p = h.at(1.0);
  // Facing the camera: the beacon's forward (model -z) points along camera -z.
  const Vec3 fwd = p.R * Vec3(0, 0, -1);
  EXPECT_LT(std::acos(std::clamp(fwd.dot(Vec3(0, 0, -1)), -1.0, 1.0)), 1.0 * kDeg);
  EXPECT_NEAR((p.t - Vec3(0, 0, 1000)).norm(), 0.0, 1.0);
}

TEST(HeadTrace, ATurnSwingsTheHeadAboutTheNeckPivot) {
  std::istringstream in(viewer_trace(0.0, 30.0, 4.0));  // the turn is short: heading 0 is held most
  HeadTraceOptions o;
  const HeadTrace h = HeadTrace::parse(in, "test", o);
  const Pose end = h.at(h.duration());
  EXPECT_NEAR(rotation_angle_between(end.R, h.at(0.0).R), 30.0 * kDeg, 0.5 * kDeg);
  // The pivot stays where it was: centre + R p = rest + p.
  EXPECT_LT((end.t + end.R * o.pivot_mm - (o.rest_mm + o.pivot_mm)).norm(), 1e-6);
  EXPECT_GT((end.t - o.rest_mm).norm(), 10.0);  // a 30 deg turn moves the centre
  // Turning to the viewer's left (+yaw about up) turns the face toward the image's right (+x).
  EXPECT_GT((end.R * Vec3(0, 0, -1)).x() - (h.at(0.0).R * Vec3(0, 0, -1)).x(), 0.3);
  // Between samples: slerp, continuous.
  for (double t = 4.0; t < 5.0; t += 0.003)
    EXPECT_LT(rotation_angle_between(h.at(t).R, h.at(t + 0.003).R), 0.2 * kDeg);
}

TEST(HeadTrace, APositionTraceFollowsItsDisplacementFromTheMean) {
  std::istringstream in(
      "t_s,qw,qx,qy,qz,x_m,y_m,z_m\n0,1,0,0,0,1.0,1.5,2.0\n1,1,0,0,0,1.2,1.5,2.0\n");
  const HeadTrace h = HeadTrace::parse(in, "test");
  ASSERT_TRUE(h.has_position());
  // x right in the source is -x in the camera frame: +0.2 m is 200 mm to -x; the mean at rest.
  EXPECT_NEAR((h.at(0.0).t - Vec3(100, 0, 1000)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((h.at(1.0).t - Vec3(-100, 0, 1000)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(rotation_angle_between(h.at(0.5).R, Mat3::Identity()), 0.0, 1e-9);
}

TEST(HeadTrace, RejectsBadFiles) {
  auto bad = [](const std::string& text) {
    std::istringstream in(text);
    EXPECT_THROW((void)HeadTrace::parse(in, "bad"), earshot::InputError) << text;
  };
  bad("");
  bad("t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0,0\n");
  bad("t_s,qw,qx,qy,qz\n0,1,0,0,0\n");
  bad("t_s,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0\n");
  bad("t_s,qw,qx,qy,qz\n1,1,0,0,0\n0,1,0,0,0\n");
  bad("t_s,qw,qx,qy,qz\n0,1,0,0,0\n1,0,0,0,0\n");
  bad("t_s,qw,qx,qy,qz\n0,1,0,0,0\n1,x,0,0,0\n");
}

TEST(HeadTrace, DrivesTheSimulatorAndLedsLeaveTheBeamOneAtATime) {
  // Heading 0 held, then a 90 deg turn: every LED leaves its 45 deg beam,
  // not all in the same frame.
  std::istringstream in(viewer_trace(0.0, 90.0, 3.0));
  SimulatorConfig cfg;
  cfg.trace = std::make_shared<const HeadTrace>(HeadTrace::parse(in, "test"));
  cfg.pixels = PixelModel::exact;
  const Camera cam;
  Simulator sim(cam, LedModel::thesis(), cfg);
  int prev = 4, steps = 0;
  bool all_seen_at_start = false;
  for (int i = 0; i < 500; ++i) {
    const DotFrame f = sim.next();
    EXPECT_LT(rotation_angle_between(f.truth->pose.R, cfg.trace->at(f.t).R), 1e-12);
    if (i == 0) all_seen_at_start = f.visible() == 4;
    if (f.visible() < prev) ++steps;
    prev = f.visible();
  }
  EXPECT_TRUE(all_seen_at_start);
  EXPECT_EQ(prev, 0);
  EXPECT_GE(steps, 2);  // the dots go in more than one step
}

TEST(Simulator, SweepReversesInOneFrameAtItsRangeEnds) {
  SimulatorConfig cfg;
  cfg.motion = MotionProfile::sweep;
  cfg.seed = 5;
  cfg.pixels = PixelModel::exact;
  const Camera cam;
  Simulator sim(cam, LedModel::thesis(), cfg);
  SpeedCollector speed;
  Pose prev2, prev;
  int reversals = 0;
  for (int i = 0; i < 6000; ++i) {
    const DotFrame f = sim.next();
    speed.add(f.truth->pose, f.t);
    if (i >= 2) {
      const Vec3 w1 = log_so3(f.truth->pose.R * prev.R.transpose());
      const Vec3 w0 = log_so3(prev.R * prev2.R.transpose());
      // A reversal: the angular velocity turns by more than 90 deg in one frame at speed.
      if (w0.norm() > 0.5 * kDeg && w1.norm() > 0.5 * kDeg && w1.dot(w0) < 0.0) ++reversals;
    }
    prev2 = prev;
    prev = f.truth->pose;
  }
  const SpeedStats st = speed.stats();
  EXPECT_GT(st.p50, 110.0);
  EXPECT_LT(st.p50, 230.0);
  EXPECT_GT(reversals, 0);
}
