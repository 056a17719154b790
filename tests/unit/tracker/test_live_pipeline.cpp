// The live pipeline frame by frame: axis conventions, recenter, levelling,
// hold-then-ease after a loss, and the simulator's injected faults (dots
// vanish, slots swap, a stray replaces an LED, garbage, the source stops):
// the state says what happened, nothing non-finite comes out, tracking
// comes back within a few frames.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/sources/wiimote_source.hpp"
#include "earshot/tracker/sources/sim_source.hpp"

using namespace earshot::tracker;
using earshot::HeadPose;
using earshot::PoseState;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Quat q_of(const HeadPose& p) { return {p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3]}; }
Vec3 pos_of(const HeadPose& p) { return {p.position[0], p.position[1], p.position[2]}; }
double angle_between(const HeadPose& a, const HeadPose& b) { return q_of(a).angularDistance(q_of(b)); }
/// Where the listener looks (audio frame: -z ahead).
Vec3 forward(const HeadPose& p) { return q_of(p) * Vec3(0, 0, -1); }

/// Camera frames of a beacon at a scripted pose (exact pixels).
struct Scripted {
  Camera cam = Camera::with_focal(1280.0);
  LedModel model = LedModel::thesis();
  Simulator sim{cam, model, [] {
                  SimulatorConfig c;
                  c.pixels = PixelModel::exact;
                  return c;
                }()};
  CameraFrame frame(const Pose& p, double t) {
    CameraFrame f;
    const DotFrame d = sim.observe(p, t);
    f.dots.t = t;
    f.dots.slots = d.slots;
    return f;
  }
};

Pose beacon(double yaw_deg, Vec3 t_mm = Vec3(0, 0, 1000)) {
  return {rotation_from_ypr(yaw_deg * kDeg, 0.0, 0.0), t_mm};
}

}  // namespace

TEST(LiveConventions, CameraToAudioFacesTheUser) {
  const Mat3 A = camera_to_audio();
  EXPECT_NEAR(A.determinant(), 1.0, 1e-12);  // a rotation: handedness kept
  EXPECT_TRUE((A * Vec3(0, 0, -1)).isApprox(Vec3(0, 0, -1)));  // towards the camera = ahead
  EXPECT_TRUE((A * Vec3(1, 0, 0)).isApprox(Vec3(-1, 0, 0)));   // camera's right = user's left
  EXPECT_TRUE((A * Vec3(0, 1, 0)).isApprox(Vec3(0, -1, 0)));   // camera's down = down
}

TEST(LiveConventions, AudioYawPitchRoll) {
  // Positive yaw turns left, positive pitch looks up, positive roll tilts right.
  EXPECT_TRUE((to_eigen(earshot::quat_from_ypr(90 * kDeg, 0, 0)) * Vec3(0, 0, -1)).isApprox(Vec3(-1, 0, 0), 1e-12));
  EXPECT_TRUE((to_eigen(earshot::quat_from_ypr(0, 90 * kDeg, 0)) * Vec3(0, 0, -1)).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE((to_eigen(earshot::quat_from_ypr(0, 0, 90 * kDeg)) * Vec3(0, 1, 0)).isApprox(Vec3(1, 0, 0), 1e-12));
}

TEST(LiveConventions, RemoteAccelerometerInCameraFrame) {
  // Face up the remote reads +1 g on its z: the camera's up is -y.
  EXPECT_TRUE(remote_accel_to_camera(Vec3(0, 0, 1)).isApprox(Vec3(0, -1, 0)));
  // Camera pointing at the floor (IR end down): +1 g on the remote's y (its back is up).
  EXPECT_TRUE(remote_accel_to_camera(Vec3(0, 1, 0)).isApprox(Vec3(0, 0, -1)));
}

TEST(LivePipeline, StartsNeutralThenFollowsTheHeadInAudioAxes) {
  Scripted s;
  LiveConfig cfg;
  cfg.tracker.filter = FilterKind::none;  // exact numbers
  LivePipeline p(cfg);
  double t = 0.0;
  HeadPose out;
  for (int i = 0; i < 10; ++i, t += 0.01) out = *p.process(s.frame(beacon(0), t), t);
  EXPECT_EQ(out.state, PoseState::tracking);
  EXPECT_NEAR(angle_between(out, HeadPose{}), 0.0, 1e-6);
  EXPECT_NEAR(pos_of(out).norm(), 0.0, 1e-6);

  // The user turns 20 degrees to their left (about the camera's up, -y) and
  // leans 100 mm towards the camera.
  for (int i = 1; i <= 20; ++i, t += 0.01) out = *p.process(s.frame(beacon(-i * 1.0, Vec3(0, 0, 1000 - 5.0 * i)), t), t);
  EXPECT_EQ(out.state, PoseState::tracking);
  EXPECT_NEAR(angle_between(out, HeadPose{}), 20 * kDeg, 1e-4);
  EXPECT_LT(forward(out).x(), -0.3);         // looks to the left
  EXPECT_NEAR(pos_of(out).z(), -0.1, 1e-4);  // moved ahead
  EXPECT_NEAR(pos_of(out).x(), 0.0, 1e-4);

  // Recenter: the current pose becomes neutral.
  p.request_recenter();
  out = *p.process(s.frame(beacon(-20, Vec3(0, 0, 900)), t), t);
  EXPECT_NEAR(angle_between(out, HeadPose{}), 0.0, 1e-6);
  EXPECT_NEAR(pos_of(out).norm(), 0.0, 1e-6);
}

TEST(LivePipeline, RecenterButtonActsOnThePress) {
  Scripted s;
  LiveConfig cfg;
  cfg.tracker.filter = FilterKind::none;
  LivePipeline p(cfg);
  double t = 0.0;
  for (int i = 0; i < 5; ++i, t += 0.01) (void)p.process(s.frame(beacon(0), t), t);
  CameraFrame f = s.frame(beacon(-15), t);
  HeadPose out = *p.process(f, t);
  EXPECT_NEAR(angle_between(out, HeadPose{}), 15 * kDeg, 1e-4);
  f.buttons = 0x0800;  // A pressed
  t += 0.01;
  f.dots.t = t;
  out = *p.process(f, t);
  EXPECT_NEAR(angle_between(out, HeadPose{}), 0.0, 1e-6);
}

TEST(LivePipeline, LevelsATiltedCameraWhenStill) {
  LiveConfig cfg;
  LivePipeline p(cfg);
  // Camera pitched 20 degrees: gravity is not along its +y. The reading is "up".
  const Vec3 down = Eigen::AngleAxisd(20 * kDeg, Vec3::UnitX()) * Vec3(0, 1, 0);
  CameraFrame f;
  f.accel_g = -down;
  for (int i = 0; i < 5; ++i) {  // moving: no levelling yet
    f.dots.t = i * 0.01;
    f.accel_g = -down * (1.0 + 0.05 * (i % 2));
    (void)p.process(f, f.dots.t);
  }
  EXPECT_TRUE(p.leveling().isIdentity(1e-12));
  f.accel_g = -down;
  for (int i = 5; i < 5 + cfg.still_frames + 1; ++i) {
    f.dots.t = i * 0.01;
    (void)p.process(f, f.dots.t);
  }
  EXPECT_TRUE((p.leveling() * down).isApprox(Vec3(0, 1, 0), 1e-9));
}

TEST(LivePipeline, LossHoldsThenEasesToNeutralAndResumesWithoutJumps) {
  Scripted s;
  LiveConfig cfg;
  cfg.tracker.filter = FilterKind::none;
  LivePipeline p(cfg);
  double t = 0.0;
  HeadPose out;
  for (int i = 0; i < 5; ++i, t += 0.01) out = *p.process(s.frame(beacon(0), t), t);
  for (int i = 1; i <= 30; ++i, t += 0.01) out = *p.process(s.frame(beacon(-i * 1.0), t), t);
  const HeadPose held = out;
  ASSERT_NEAR(angle_between(held, HeadPose{}), 30 * kDeg, 1e-4);

  // Nothing seen for 3 s: predicted for 0.1 s (the motion extrapolated),
  // then lost: held, then eased to neutral.
  double max_step = 0.0;
  HeadPose prev = out;
  std::optional<HeadPose> at_loss;
  for (int i = 0; i < 300; ++i, t += 0.01) {
    CameraFrame empty;
    empty.dots.t = t;
    out = *p.process(empty, t);
    ASSERT_TRUE(out.finite());
    max_step = std::max(max_step, angle_between(out, prev));
    prev = out;
    const double since = t - 0.34;  // last good frame at t = 0.34
    if (since > cfg.tracker.predict_timeout_s + 1e-9) {
      EXPECT_EQ(out.state, PoseState::lost) << t;
    }
    if (out.state == PoseState::lost && !at_loss) at_loss = out;
    if (at_loss && since <= cfg.hold_s - 0.01) {
      EXPECT_NEAR(angle_between(out, *at_loss), 0.0, 1e-9) << t;
    }
  }
  EXPECT_NEAR(angle_between(out, HeadPose{}), 0.0, 1e-9);  // eased all the way to neutral
  EXPECT_LT(max_step, 1.0 * kDeg);                         // and never jumped

  // The head is back at 30 degrees: tracking at once, blending in smoothly.
  max_step = 0.0;
  for (int i = 0; i < 30; ++i, t += 0.01) {
    out = *p.process(s.frame(beacon(-30), t), t);
    max_step = std::max(max_step, angle_between(out, prev));
    prev = out;
    EXPECT_EQ(out.state, PoseState::tracking);
  }
  EXPECT_LT(max_step, 6.0 * kDeg);
  EXPECT_NEAR(angle_between(out, held), 0.0, 1e-4);
}

TEST(LivePipeline, GarbageDotsAreRejectedNeverTrusted) {
  LivePipeline p;
  CameraFrame f;
  f.dots.t = 0.0;
  const double nan = std::nan("");
  f.dots.slots = {Vec2(nan, 1), Vec2(2000, 10), Vec2(-1, 5), Vec2(10, INFINITY)};
  const auto out = p.process(f, 0.0);
  ASSERT_TRUE(out && out->finite());
  EXPECT_EQ(out->state, PoseState::searching);
  EXPECT_EQ(p.counters().rejected_dots, 4u);
  f.dots.t = nan;  // a frame without a time publishes nothing
  EXPECT_FALSE(p.process(f, 0.0).has_value());
}

namespace {

struct FaultRun {
  std::vector<HeadPose> poses;
  std::vector<bool> frame;  // true: a camera frame (not a silence note)
};

FaultRun run_with_faults(std::vector<Fault> faults, long frames) {
  const Camera cam = Camera::with_focal(1280.0);
  SimSourceConfig sc;
  sc.sim.motion = MotionProfile::walk;  // the walk over the box set below
  sc.sim.seed = 5;
  sc.sim.yaw_max_deg = 25;
  sc.sim.pitch_max_deg = 15;
  sc.sim.roll_max_deg = 20;
  sc.sim.z_min_mm = 800;
  sc.sim.z_max_mm = 1300;
  sc.sim.lateral_fraction = 0.4;
  sc.pacing = Pacing::as_fast_as_possible;
  sc.frames = frames;
  sc.faults = std::move(faults);
  SimSource src(cam, LedModel::thesis(), sc);
  LivePipeline p;
  FaultRun r;
  for (;;) {
    const SourceEvent e = src.next(std::chrono::milliseconds(0));
    const auto* n = std::get_if<SourceNote>(&e);
    if (n && n->kind == SourceNote::Kind::ended) break;
    const double now = n && n->t ? *n->t : 0.0;
    const auto out = p.process(e, now);
    EXPECT_TRUE(out.has_value());
    r.poses.push_back(*out);
    r.frame.push_back(n == nullptr);
  }
  return r;
}

/// Frames from `from` until the state is tracking again.
long frames_to_track(const FaultRun& r, long from) {
  for (long i = from; i < static_cast<long>(r.poses.size()); ++i)
    if (r.poses[static_cast<std::size_t>(i)].state == PoseState::tracking) return i - from;
  return 1'000'000;
}

}  // namespace

TEST(LiveFaults, BaselineWalkTracksEveryFrame) {
  const FaultRun r = run_with_faults({}, 600);
  long tracking = 0;
  for (const auto& p : r.poses) tracking += p.state == PoseState::tracking;
  EXPECT_GE(tracking, 598);  // the fault tests below start from a clean walk
}

TEST(LiveFaults, EveryFaultIsReportedNothingNonFiniteAndTrackingRecovers) {
  using FK = Fault::Kind;
  std::vector<Fault> faults{
      {FK::vanish, 100, 30},                     // all dots gone for 0.3 s
      {FK::swap, 200, 40, 0, 2},                 // two dots exchange slots
      {FK::stray, 300, 20, 1, 0, {200.0, 150.0}},  // a reflection where an LED was
      {FK::garbage, 400, 10},                    // NaN and out-of-image coordinates
      {FK::silence, 500, 50},                    // the source stops for 0.5 s
      {FK::drop_one, 600, 30, 3},                // one LED hidden: three dots
  };
  const FaultRun r = run_with_faults(faults, 700);
  ASSERT_EQ(r.poses.size(), 700u);
  for (const auto& p : r.poses) ASSERT_TRUE(p.finite());
  auto state = [&](long i) { return r.poses[static_cast<std::size_t>(i)].state; };

  // Vanish: predicted briefly, then lost; tracking within 3 frames of the dots' return.
  EXPECT_EQ(state(100), PoseState::predicted);
  EXPECT_EQ(state(125), PoseState::lost);
  EXPECT_LE(frames_to_track(r, 130), 3);
  // Swapped slots and a stray: the labeller follows the LEDs, not the slots.
  for (long i = 200; i < 240; ++i) EXPECT_NE(state(i), PoseState::lost) << i;
  for (long i = 300; i < 320; ++i) EXPECT_NE(state(i), PoseState::lost) << i;
  // Garbage: every dot rejected, the pose is predicted (never solved from garbage).
  for (long i = 400; i < 410; ++i) EXPECT_NE(state(i), PoseState::tracking) << i;
  EXPECT_LE(frames_to_track(r, 410), 3);
  // Silence: the timeouts report it: predicted then lost; back within 3 frames.
  EXPECT_FALSE(r.frame[520]);
  EXPECT_EQ(state(540), PoseState::lost);
  EXPECT_LE(frames_to_track(r, 550), 3);
  // Three dots: still tracking.
  long tracked3 = 0;
  for (long i = 600; i < 630; ++i) tracked3 += state(i) == PoseState::tracking;
  EXPECT_GE(tracked3, 28);
}
