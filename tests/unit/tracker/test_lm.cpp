#include <gtest/gtest.h>

#include <random>

#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/lm_solver.hpp"
#include "random_poses.hpp"

using namespace earshot::tracker;

TEST(LmRefine, JacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(3);
  const Camera cam;
  const LedModel model;
  for (int i = 0; i < 200; ++i) {
    const Pose p = fixtures::random_visible_pose(rng, cam, model);
    for (const auto& led : model.leds_mm) {
      const auto J = reprojection_jacobian(p, led, cam);
      Eigen::Matrix<double, 2, 6> N;
      const double h = 1e-6;
      for (int k = 0; k < 6; ++k) {
        Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
        d[k] = h;
        const Pose plus{exp_so3(d.head<3>()) * p.R, p.t + d.tail<3>()};
        const Pose minus{exp_so3(-d.head<3>()) * p.R, p.t - d.tail<3>()};
        N.col(k) = (cam.project(plus.apply(led)) - cam.project(minus.apply(led))) / (2 * h);
      }
      EXPECT_LT((J - N).norm(), 1e-5 * (1.0 + N.norm())) << "pose " << i;
    }
  }
}

TEST(LmRefine, ConvergesToExactPoseFromPerturbedStart) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  const Camera cam;
  const LedModel model;
  for (int i = 0; i < 1000; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    const auto dots = fixtures::exact_dots(truth, cam, model);
    const Pose start{exp_so3(Vec3(n(rng), n(rng), n(rng)) * 0.03) * truth.R,
                     truth.t + Vec3(n(rng), n(rng), n(rng)) * 10.0};
    const auto r = refine_pose_lm(start, dots.view(), cam, model);
    EXPECT_TRUE(r.converged);
    EXPECT_LT(rotation_angle_between(r.pose.R, truth.R), 1e-7) << "pose " << i;
    EXPECT_LT((r.pose.t - truth.t).norm(), 1e-5) << "pose " << i;
  }
}

TEST(LmSolver, RecoversExactPosesWithoutPriorOverFullRoll) {
  std::mt19937_64 rng(9);
  const Camera cam;
  const LedModel model;
  LmSolver solver(cam, model);
  for (int i = 0; i < 1000; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    const auto dots = fixtures::exact_dots(truth, cam, model);
    const auto p = solver.solve({dots.view(), nullptr});
    ASSERT_TRUE(p.has_value()) << "pose " << i;
    EXPECT_LT(rotation_angle_between(p->R, truth.R), 1e-6) << "pose " << i;
    EXPECT_LT((p->t - truth.t).norm(), 1e-4) << "pose " << i;
  }
}

TEST(LmSolver, ThreeDotsWithPriorLandsNearTheTruth) {
  // Three dots fit a whole family of poses almost equally (and every P3P
  // root exactly); the solver takes the P3P root nearest the prior and then
  // weighs the prior in (MAP). The result must be nearer the truth than the
  // prior was, and still fit the dots to a fraction of a pixel.
  std::mt19937_64 rng(13);
  const Camera cam;
  const LedModel model;
  LmSolver solver(cam, model);
  int far = 0;
  for (int i = 0; i < 1000; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    auto all = fixtures::exact_dots(truth, cam, model);
    LabelledDots three;
    for (int k = 0; k < 4; ++k)
      if (k != i % 4) three.add(all.items[static_cast<size_t>(k)].led, all.items[static_cast<size_t>(k)].pixel);
    const Pose prior{exp_so3(Vec3(0.02, -0.01, 0.015)) * truth.R, truth.t + Vec3(5, -3, 8)};
    const auto p = solver.solve({three.view(), &prior});
    ASSERT_TRUE(p.has_value());
    EXPECT_LT(rms_reprojection_error(*p, three.view(), cam, model), 0.5) << "pose " << i;
    const double prior_err = rotation_angle_between(prior.R, truth.R);
    if (rotation_angle_between(p->R, truth.R) >= prior_err) ++far;
  }
  EXPECT_LE(far, 20);
}

TEST(LmSolver, ThreeDotsWithoutPriorIsRefused) {
  std::mt19937_64 rng(1);
  const Camera cam;
  const LedModel model;
  LmSolver solver(cam, model);
  const auto all = fixtures::exact_dots(fixtures::random_visible_pose(rng, cam, model), cam, model);
  LabelledDots three;
  for (int k = 0; k < 3; ++k) three.add(k, all.items[static_cast<size_t>(k)].pixel);
  EXPECT_FALSE(solver.solve({three.view(), nullptr}).has_value());
}
