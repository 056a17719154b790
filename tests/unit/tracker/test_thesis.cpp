#include <gtest/gtest.h>

#include <random>

#include "earshot/tracker/solve/thesis_solver.hpp"
#include "random_poses.hpp"

using namespace earshot::tracker;

TEST(ThesisSolver, RecoversExactPosesFromNoiseFreeDots) {
  // Without the median filter each frame stands alone; the distances start
  // from the previous frame's, as in the thesis, so the walk is continuous.
  std::mt19937_64 rng(21);
  const Camera cam;
  const LedModel model;
  ThesisSolver solver(cam, model, /*median_filter=*/false);
  Pose p = fixtures::random_visible_pose(rng, cam, model);
  std::normal_distribution<double> n(0.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 1000; ++i) {
    // Small steps between frames, like a head at 100 Hz; any roll reached over time.
    Pose next{exp_so3(Vec3(n(rng), n(rng), 3 * n(rng)) * 0.01) * p.R, p.t + Vec3(n(rng), n(rng), n(rng)) * 3.0};
    bool inside = true;
    for (const auto& led : model.leds_mm) inside = inside && cam.inside(cam.project(next.apply(led)));
    if (!inside || next.t.z() < 500 || next.t.z() > 1700) continue;
    p = next;
    const auto dots = fixtures::exact_dots(p, cam, model);
    const auto est = solver.solve({dots.view(), nullptr});
    ASSERT_TRUE(est.has_value());
    EXPECT_LT(rotation_angle_between(est->R, p.R), 1e-6) << "frame " << i;
    EXPECT_LT((est->t - p.t).norm(), 1e-4) << "frame " << i;
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST(ThesisSolver, MedianFilterDelaysARampByTwoFrames) {
  const Camera cam;
  const LedModel model;
  ThesisSolver solver(cam, model, /*median_filter=*/true);
  EXPECT_EQ(solver.latency_frames(), 2);
  std::vector<Pose> truth;
  for (int i = 0; i < 12; ++i) {
    const Pose p{Mat3::Identity(), Vec3(0, 0, 1000.0 + 10.0 * i)};
    truth.push_back(p);
    const auto est = solver.solve({fixtures::exact_dots(p, cam, model).view(), nullptr});
    ASSERT_TRUE(est.has_value());
    // Distances come from two frames back; the rays are this frame's (eq. 49),
    // so the delayed pose is slightly off the old one, far from the new one.
    if (i >= 4) {
      EXPECT_NEAR(est->t.z(), truth[static_cast<size_t>(i - 2)].t.z(), 0.2);
      EXPECT_GT(std::abs(est->t.z() - p.t.z()), 19.0);
    }
  }
}

TEST(ThesisSolver, NeedsAllFourDots) {
  const Camera cam;
  const LedModel model;
  ThesisSolver solver(cam, model);
  auto dots = fixtures::exact_dots(Pose{Mat3::Identity(), Vec3(0, 0, 1000)}, cam, model);
  dots.count = 3;
  EXPECT_FALSE(solver.solve({dots.view(), nullptr}).has_value());
}

TEST(AbsoluteOrientation, RecoversARigidTransform) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0.0, 1.0);
  const LedModel model;
  for (int i = 0; i < 200; ++i) {
    const Pose truth{exp_so3(Vec3(n(rng), n(rng), n(rng))), Vec3(n(rng), n(rng), n(rng)) * 100.0};
    std::array<Vec3, 4> measured;
    for (size_t k = 0; k < 4; ++k) measured[k] = truth.apply(model.leds_mm[k]);
    const Pose est = absolute_orientation(model.leds_mm, measured);
    EXPECT_LT(rotation_angle_between(est.R, truth.R), 1e-9);
    EXPECT_LT((est.t - truth.t).norm(), 1e-9);
  }
}
