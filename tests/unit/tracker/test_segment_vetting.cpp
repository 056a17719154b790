// The smoother's segment vetting (segment_vetting.hpp) and the motion reach
// it shares with the dot tracker (motion_reach.hpp), on filter steps made by
// the eskf itself from a head turning at a steady rate.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/filter/motion_reach.hpp"
#include "earshot/tracker/filter/segment_vetting.hpp"

using namespace earshot::tracker;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kRate = 100.0;  // Hz

/// The true pose of a head yawing at `deg_s` about a point 1 m away.
Pose head_at(double t, double deg_s) { return {rotation_from_ypr(deg_s * kDeg * t, 0.1, 0.0), Vec3(20.0, -10.0, 1000.0)}; }

/// Integer-pixel-sized measurement noise on the thesis beacon (~0.2 deg, ~1 mm).
Mat6 measurement_cov() {
  Mat6 c = Mat6::Zero();
  c.diagonal() << 1.2e-5, 1.2e-5, 1.2e-5, 1.0, 1.0, 1.0;
  return c;
}

/// One stretch the filter follows: frames [from, to) of the turn, each pose
/// rotated by `wrong_deg` about the camera axis (a wrong branch) if nonzero.
struct Stretch {
  int from, to;
  double wrong_deg = 0.0;
};

/// The eskf's steps over the stretches, restarted at each (as the dot
/// tracker does on a re-acquisition), with Gaussian measurement noise.
std::vector<EskfStep> steps_of(const std::vector<Stretch>& stretches, double deg_s, unsigned seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const Mat6 cov = measurement_cov();
  const double sr = std::sqrt(cov(0, 0)), st = std::sqrt(cov(3, 3));
  PoseEskf eskf;
  std::vector<EskfStep> out;
  for (const Stretch& s : stretches) {
    eskf.reset();
    for (int i = s.from; i < s.to; ++i) {
      const double t = i / kRate;
      Pose z = head_at(t, deg_s);
      if (s.wrong_deg != 0.0) z.R = exp_so3(Vec3(0.0, 0.0, s.wrong_deg * kDeg)) * z.R;
      z = {exp_so3(sr * Vec3(n(rng), n(rng), n(rng))) * z.R, z.t + st * Vec3(n(rng), n(rng), n(rng))};
      eskf.update(z, cov, t);
      out.push_back(eskf.last_step());
    }
  }
  return out;
}

std::vector<bool> vet(const std::vector<EskfStep>& steps) {
  RtsSmoother smoother;
  for (const auto& s : steps) smoother.add(s);
  return vet_segments(smoother.segments(), smoother.size(), EskfParams{});
}

long dropped(const std::vector<bool>& kept, std::size_t from, std::size_t to) {
  long n = 0;
  for (std::size_t i = from; i < to; ++i) n += kept[i] ? 0 : 1;
  return n;
}

}  // namespace

TEST(MotionReach, CarriedStateReachesWhatAHeadCanDoAndNotAJump) {
  // A head turning at 200 deg/s, followed for 0.3 s, then 20 ms unseen (at
  // the largest manoeuvre noise, 50 ms would already reach ~45 degrees).
  const std::vector<EskfStep> steps = steps_of({{0, 30}}, 200.0);
  const EskfStep& last = steps.back();
  const double t = 0.31;
  EXPECT_LT(carried_mahalanobis2(last, EskfParams{}, t, head_at(t, 200.0)), kChi2SixDof999);
  // The same instant 45 degrees off about the camera axis: another root.
  Pose wrong = head_at(t, 200.0);
  wrong.R = exp_so3(Vec3(0.0, 0.0, 45.0 * kDeg)) * wrong.R;
  EXPECT_GT(carried_mahalanobis2(last, EskfParams{}, t, wrong), kChi2SixDof999);
  // A wide measurement covariance of the later pose widens the reach.
  const Mat6 wide = Mat6::Identity() * 1.0;
  EXPECT_LT(carried_mahalanobis2(last, EskfParams{}, t, wrong, wide), kChi2SixDof999);
}

TEST(MotionReach, OuDisplacementIsWhiteAccelerationsWhenShortAndLinearWhenLong) {
  const double q = 1.0, tau = 0.5;
  // dt << tau: q dt^3 / 3; dt >> tau: q tau^2 dt (a random walk of position).
  EXPECT_NEAR(ou_displacement_variance(q, tau, 0.01) / (q * 1e-6 / 3.0), 1.0, 0.02);
  EXPECT_NEAR(ou_displacement_variance(q, tau, 100.0) / (q * tau * tau * 100.0), 1.0, 0.02);
}

TEST(SegmentVetting, DropsAWrongBranchBetweenTwoRightOnes) {
  // 0.5 s right, 80 ms on a branch 45 degrees off, 0.5 s right; 10 ms gaps.
  const std::vector<EskfStep> steps = steps_of({{0, 50}, {51, 59, 45.0}, {60, 110}}, 150.0);
  const std::vector<bool> kept = vet(steps);
  ASSERT_EQ(kept.size(), 108u);
  EXPECT_EQ(dropped(kept, 0, 50), 0);
  EXPECT_EQ(dropped(kept, 50, 58), 8);
  EXPECT_EQ(dropped(kept, 58, 108), 0);
}

TEST(SegmentVetting, DropsTheWrongOneOfTwoRestartsInARow) {
  // Right, right (restarted), wrong, right: the wrong one goes, both right
  // ones next to it stay (the most outlying segment is judged first).
  const std::vector<EskfStep> steps = steps_of({{0, 40}, {41, 70}, {71, 76, -60.0}, {77, 120}}, 150.0);
  const std::vector<bool> kept = vet(steps);
  EXPECT_EQ(dropped(kept, 0, 69), 0);
  EXPECT_EQ(dropped(kept, 69, 74), 5);
  EXPECT_EQ(dropped(kept, 74, kept.size()), 0);
}

TEST(SegmentVetting, KeepsRightSegmentsAcrossGapsOfAFastTurn) {
  // 400 deg/s with 40 ms losses between restarts: every segment is right,
  // though the head turned 16 degrees while unseen each time.
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::vector<EskfStep> steps = steps_of({{0, 30}, {34, 44}, {48, 80}, {84, 90}, {94, 140}}, 400.0, seed);
    const std::vector<bool> kept = vet(steps);
    EXPECT_EQ(dropped(kept, 0, kept.size()), 0) << "seed " << seed;
  }
}

TEST(SegmentVetting, GivesNoVerdictBeyondTheFiltersHorizon) {
  // The wrong stretch lies between losses longer than the eskf links (0.25 s
  // each side): nothing connects its neighbours, so nothing is dropped.
  const std::vector<EskfStep> steps = steps_of({{0, 50}, {80, 88, 45.0}, {118, 160}}, 150.0);
  EXPECT_EQ(dropped(vet(steps), 0, steps.size()), 0);
}

TEST(SegmentVetting, KeepsTheEnds) {
  // A wrong first or last segment has only one neighbour: no verdict.
  const std::vector<EskfStep> first = steps_of({{0, 8, 45.0}, {9, 60}, {61, 100}}, 150.0);
  EXPECT_EQ(dropped(vet(first), 0, first.size()), 0);
  const std::vector<EskfStep> last = steps_of({{0, 50}, {51, 90}, {91, 99, 45.0}}, 150.0);
  EXPECT_EQ(dropped(vet(last), 0, last.size()), 0);
  EXPECT_EQ(vet(steps_of({{0, 50}}, 150.0)).size(), 50u);
}

TEST(RtsSmootherSegments, AreTheStretchesBetweenRestartsWithTheirEndStates) {
  const std::vector<EskfStep> steps = steps_of({{0, 50}, {51, 59, 45.0}, {60, 110}}, 150.0);
  RtsSmoother smoother;
  for (const auto& s : steps) smoother.add(s);
  const std::vector<EskfSegment> segs = smoother.segments();
  ASSERT_EQ(segs.size(), 3u);
  const std::size_t bounds[3][2] = {{0, 49}, {50, 57}, {58, 107}};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(segs[k].first, bounds[k][0]);
    EXPECT_EQ(segs[k].last, bounds[k][1]);
    const EskfStep& first = steps[segs[k].first];
    const EskfStep& last = steps[segs[k].last];
    EXPECT_EQ(segs[k].t_first, first.t);
    EXPECT_TRUE(segs[k].first_pose.R.isApprox(first.pose_upd.R));
    EXPECT_TRUE(segs[k].first_cov.isApprox(first.P_upd.topLeftCorner<6, 6>()));
    EXPECT_EQ(segs[k].end.t, last.t);
    EXPECT_TRUE(segs[k].end.pose_upd.R.isApprox(last.pose_upd.R));
    EXPECT_TRUE(segs[k].end.w_upd.isApprox(last.w_upd));
    EXPECT_TRUE(segs[k].end.P_upd.isApprox(last.P_upd));
  }
}
