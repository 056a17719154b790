// Head prediction: the live pipeline's pose carries the eskf's velocities,
// and earshot::extrapolate carries it on to when the audio block is heard.
// A head turning at a constant rate, read a latency after each frame: the
// extrapolated pose is within a small angle of the truth then, the pose as
// it stands lags by the rate times the latency. Nothing is extrapolated
// outside the tracking state, beyond the cap, or without a steady time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#include "earshot/head_pose.hpp"
#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/tracker/sim/simulator.hpp"

using namespace earshot::tracker;
using earshot::HeadPose;
using earshot::PoseState;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Quat q_of(const HeadPose& p) { return {p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3]}; }

/// The steady clock the pipeline stamps with: the test sets it per frame.
double g_steady = 0.0;
double test_clock() { return g_steady; }

struct TurnResult {
  double lag_raw_ms = 0.0;   ///< mean angle behind the truth / rate, the pose as it stands
  double lag_pred_ms = 0.0;  ///< the same, extrapolated
  double rms_raw_deg = 0.0, rms_pred_deg = 0.0;
  int frames = 0;
};

/// A beacon yawing at `rate_deg_s` through +-35 deg at 100 Hz; each frame's
/// pose is read `latency_s` later and compared with the truth then (in the
/// audio frame, relative to the first frame, which the pipeline takes as
/// neutral).
TurnResult turn(double rate_deg_s, double latency_s, PixelModel pixels) {
  const Camera cam = Camera::with_focal(1280.0);
  const LedModel model = LedModel::thesis();
  SimulatorConfig sc;
  sc.pixels = pixels;
  Simulator sim(cam, model, sc);
  sc.pixels = PixelModel::exact;
  Simulator exact(cam, model, sc);  // the first frame: the reference the pipeline takes as neutral is the truth
  LivePipeline pipe;
  pipe.set_steady_clock(&test_clock);
  const double rate = rate_deg_s * kDeg, span = 70.0 * kDeg, dt = 0.01;
  const auto truth = [&](double t) { return rotation_from_ypr(-0.5 * span + rate * t, 0.1, 0.05); };
  const Mat3 A = camera_to_audio();
  const Mat3 ref = truth(0.0);
  TurnResult out;
  double sum_raw = 0.0, sum_pred = 0.0, ss_raw = 0.0, ss_pred = 0.0;
  const int n = static_cast<int>(span / rate / dt);
  for (int k = 0; k <= n; ++k) {
    const double t = k * dt;
    g_steady = 1000.0 + t;
    CameraFrame f;
    const DotFrame d = (k == 0 ? exact : sim).observe(Pose{truth(t), Vec3(20, -10, 1000)}, t);
    f.dots.t = t;
    f.dots.slots = d.slots;
    const auto h = pipe.process(f, t);
    if (!h || h->state != PoseState::tracking) continue;
    if (k < 8) continue;  // the filter's velocity settles from its first frames
    const HeadPose heard = earshot::extrapolate(*h, g_steady + latency_s);
    const Quat want(Mat3(A * truth(t + latency_s) * ref.transpose() * A.transpose()));
    const double e_raw = q_of(*h).angularDistance(want), e_pred = q_of(heard).angularDistance(want);
    sum_raw += e_raw;
    sum_pred += e_pred;
    ss_raw += e_raw * e_raw;
    ss_pred += e_pred * e_pred;
    ++out.frames;
  }
  if (out.frames > 0) {
    const double m = out.frames;
    out.lag_raw_ms = 1e3 * sum_raw / m / rate;
    out.lag_pred_ms = 1e3 * sum_pred / m / rate;
    out.rms_raw_deg = std::sqrt(ss_raw / m) / kDeg;
    out.rms_pred_deg = std::sqrt(ss_pred / m) / kDeg;
  }
  return out;
}

/// A still head seen with Gaussian pixel noise: RMS angle off the truth of
/// the pose as it stands and extrapolated by `latency_s` (deg). Extrapolating
/// a still head moves it only by its velocity's noise.
std::pair<double, double> still_jitter(double noise_px, double latency_s) {
  const Camera cam = Camera::with_focal(1280.0);
  const LedModel model = LedModel::thesis();
  SimulatorConfig sc;
  sc.pixels = PixelModel::gaussian;
  sc.noise_px = noise_px;
  Simulator sim(cam, model, sc);
  sc.pixels = PixelModel::exact;
  Simulator exact(cam, model, sc);
  LivePipeline pipe;
  pipe.set_steady_clock(&test_clock);
  const Pose head{rotation_from_ypr(0.2, 0.1, 0.05), Vec3(20, -10, 1000)};
  double ss_raw = 0.0, ss_pred = 0.0;
  int n = 0;
  for (int k = 0; k < 500; ++k) {
    const double t = 0.01 * k;
    g_steady = 3000.0 + t;
    CameraFrame f;
    f.dots.t = t;
    f.dots.slots = (k == 0 ? exact : sim).observe(head, t).slots;
    const auto h = pipe.process(f, t);
    if (!h || h->state != PoseState::tracking || k < 50) continue;
    const earshot::Quat id = earshot::kIdentityQuat;  // the truth: where the first frame put neutral
    const Quat want(id[0], id[1], id[2], id[3]);
    const double e_raw = q_of(*h).angularDistance(want);
    const double e_pred = q_of(earshot::extrapolate(*h, g_steady + latency_s)).angularDistance(want);
    ss_raw += e_raw * e_raw;
    ss_pred += e_pred * e_pred;
    ++n;
  }
  return {std::sqrt(ss_raw / n) / kDeg, std::sqrt(ss_pred / n) / kDeg};
}

HeadPose turning_pose(PoseState state) {
  HeadPose p;
  p.state = state;
  p.steady_s = 50.0;
  p.position = {0.1, 0.0, 0.0};
  p.angular_velocity = {0.0, 2.0, 0.0};  // 115 deg/s about up
  p.velocity = {0.5, 0.0, 0.0};
  return p;
}

}  // namespace

// 25 ms: a pose read half a 100 Hz frame after it was computed, heard one
// 128-frame block at 48 kHz (2.7 ms) plus a host's 2 x 256-frame buffer
// (10.7 ms) later, with a few ms to spare.
constexpr double kLatency = 0.025;

TEST(HeadPrediction, ConstantTurnIsCarriedToWhenTheBlockIsHeard) {
  for (double rate : {90.0, 270.0}) {
    const TurnResult r = turn(rate, kLatency, PixelModel::exact);
    ASSERT_GT(r.frames, 5) << rate;
    // As it stands the pose is a whole latency behind (the filter adds nothing
    // on a constant turn); carried on, within a small angle of the truth.
    EXPECT_GT(r.lag_raw_ms, 0.9 * kLatency * 1e3) << rate;
    EXPECT_LT(r.rms_pred_deg, 0.1) << rate;
    EXPECT_LT(r.lag_pred_ms, 1.0) << rate;
  }
}

TEST(HeadPrediction, LagTableAt30To500DegPerSecond) {
  // The figures for docs/BENCHMARKS.md: exact pixels (the lag alone) and the
  // Wii camera's integer pixels (the velocity's noise adds jitter).
  std::printf("latency %.0f ms; lag = mean angle behind the truth / rate\n", kLatency * 1e3);
  std::printf("| deg/s | pixels | frames | lag as it stands (ms) | lag extrapolated (ms) | RMS error as it stands (deg) | RMS error extrapolated (deg) |\n");
  for (const PixelModel px : {PixelModel::exact, PixelModel::integer})
    for (double rate : {30.0, 90.0, 270.0, 500.0}) {
      const TurnResult r = turn(rate, kLatency, px);
      std::printf("| %.0f | %s | %d | %.1f | %.1f | %.3f | %.3f |\n", rate, px == PixelModel::exact ? "exact" : "integer",
                  r.frames, r.lag_raw_ms, r.lag_pred_ms, r.rms_raw_deg, r.rms_pred_deg);
      ASSERT_GT(r.frames, 3);
      // Extrapolating must pay at every rate, noise included; from 90 deg/s
      // on it at least halves the error.
      EXPECT_LT(r.rms_pred_deg, (rate >= 90.0 ? 0.5 : 1.0) * r.rms_raw_deg) << rate;
    }
  // The price on a still head: the velocity's noise, carried 25 ms on.
  for (double noise : {0.1, 0.3}) {
    const auto [raw, pred] = still_jitter(noise, kLatency);
    std::printf("still head, Gaussian %.1f px: RMS error as it stands %.3f deg, extrapolated %.3f deg\n", noise, raw, pred);
    EXPECT_LT(pred, 2.0 * raw) << noise;
  }
}

TEST(HeadPrediction, ExtrapolatesOnlyWhileTracking) {
  for (const PoseState s : {PoseState::predicted, PoseState::lost, PoseState::searching}) {
    const HeadPose p = turning_pose(s);
    const HeadPose q = earshot::extrapolate(p, 50.04);
    EXPECT_EQ(q.orientation, p.orientation) << static_cast<int>(s);
    EXPECT_EQ(q.position, p.position) << static_cast<int>(s);
  }
  const HeadPose q = earshot::extrapolate(turning_pose(PoseState::tracking), 50.04);
  EXPECT_NEAR(q.position[0], 0.1 + 0.5 * 0.04, 1e-12);
  // 2 rad/s for 40 ms about +y: the quaternion's half angle is 0.04 rad.
  EXPECT_NEAR(q.orientation[0], std::cos(0.04), 1e-12);
  EXPECT_NEAR(q.orientation[2], std::sin(0.04), 1e-12);
}

TEST(HeadPrediction, CappedAheadAndNeverBackwards) {
  const HeadPose p = turning_pose(PoseState::tracking);
  const HeadPose far = earshot::extrapolate(p, 51.0);  // a second on: only the cap
  EXPECT_NEAR(far.position[0], 0.1 + 0.5 * earshot::kMaxHeadPredictionS, 1e-12);
  EXPECT_NEAR(far.steady_s, 50.0 + earshot::kMaxHeadPredictionS, 1e-12);
  const HeadPose before = earshot::extrapolate(p, 49.0);  // a read older than the pose
  EXPECT_EQ(before.orientation, p.orientation);
  HeadPose unknown = p;
  unknown.steady_s = 0.0;  // no steady time: the pose's age is unknown
  EXPECT_EQ(earshot::extrapolate(unknown, 50.04).orientation, p.orientation);
}

TEST(HeadPrediction, PipelineCarriesNoVelocityWithoutTheEskf) {
  // One Euro has no velocity state: the pose goes out as it is.
  const Camera cam = Camera::with_focal(1280.0);
  LiveConfig cfg;
  cfg.tracker.filter = FilterKind::one_euro;
  LivePipeline pipe(cfg);
  pipe.set_steady_clock(&test_clock);
  SimulatorConfig sc;
  sc.pixels = PixelModel::exact;
  Simulator sim(cam, cfg.model, sc);
  std::optional<HeadPose> h;
  for (int k = 0; k < 20; ++k) {
    const double t = 0.01 * k;
    g_steady = 2000.0 + t;
    CameraFrame f;
    f.dots.t = t;
    f.dots.slots = sim.observe(Pose{rotation_from_ypr(k * 0.02, 0.0, 0.0), Vec3(0, 0, 1000)}, t).slots;
    h = pipe.process(f, t);
  }
  ASSERT_TRUE(h && h->state == PoseState::tracking);
  EXPECT_EQ(h->angular_velocity, (earshot::Vec3{0.0, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(h->steady_s, 2000.19);
}
