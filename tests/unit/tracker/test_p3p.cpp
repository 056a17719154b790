#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "earshot/tracker/solve/p3p.hpp"
#include "random_poses.hpp"

using namespace earshot::tracker;

namespace {

/// Independent reference: every real P3P solution by a dense 1D scan of the
/// depth l1. Given l1, the constraints |l1 y1 - l2 y2|^2 = a12 and
/// |l1 y1 - l3 y3|^2 = a13 give l2 and l3 (two branches each); the roots of
/// the remaining constraint are bracketed on a fine grid and bisected.
std::vector<Eigen::Vector3d> reference_depths(const std::array<Vec3, 3>& y, const std::array<Vec3, 3>& x) {
  const double b12 = y[0].dot(y[1]), b13 = y[0].dot(y[2]);
  const double a12 = (x[0] - x[1]).squaredNorm(), a13 = (x[0] - x[2]).squaredNorm(),
               a23 = (x[1] - x[2]).squaredNorm();
  std::vector<Eigen::Vector3d> out;
  const double lmax = std::min(std::sqrt(a12 / (1 - b12 * b12)), std::sqrt(a13 / (1 - b13 * b13)));
  for (int s2 : {-1, 1})
    for (int s3 : {-1, 1}) {
      auto g = [&](double l1, Eigen::Vector3d* L) -> double {
        const double d2 = b12 * b12 * l1 * l1 - l1 * l1 + a12, d3 = b13 * b13 * l1 * l1 - l1 * l1 + a13;
        if (d2 < 0 || d3 < 0) return std::nan("");
        const double l2 = b12 * l1 + s2 * std::sqrt(d2), l3 = b13 * l1 + s3 * std::sqrt(d3);
        if (L) *L = {l1, l2, l3};
        if (l2 <= 0 || l3 <= 0) return std::nan("");
        return (l2 * y[1] - l3 * y[2]).squaredNorm() - a23;
      };
      const int n = 60000;
      double prev = NAN, prev_l = 0;
      for (int i = 1; i <= n; ++i) {
        const double l = lmax * i / n;
        const double v = g(l, nullptr);
        if (std::isfinite(v) && std::isfinite(prev) && (v == 0 || (v > 0) != (prev > 0))) {
          double lo = prev_l, hi = l;
          for (int k = 0; k < 100; ++k) {
            const double mid = 0.5 * (lo + hi);
            ((g(mid, nullptr) > 0) == (prev > 0) ? lo : hi) = mid;
          }
          Eigen::Vector3d L;
          g(0.5 * (lo + hi), &L);
          out.push_back(L);
        }
        prev = v;
        prev_l = l;
      }
    }
  return out;
}

}  // namespace

TEST(P3P, RecoversTheTruePoseAmongItsSolutions) {
  std::mt19937_64 rng(7);
  const Camera cam;
  const LedModel model;
  int worst_rank = 0;
  for (int i = 0; i < 2000; ++i) {
    const Pose truth = fixtures::random_visible_pose(rng, cam, model);
    std::array<Vec3, 3> y, x;
    for (size_t k = 0; k < 3; ++k) {
      x[k] = model.leds_mm[k + (i % 2)];
      y[k] = truth.apply(x[k]).normalized();
    }
    const auto sols = p3p_lambda_twist(y, x);
    ASSERT_GE(sols.count, 1) << "pose " << i;
    double best = 1e9;
    for (int k = 0; k < sols.count; ++k) {
      const auto& p = sols.poses[static_cast<size_t>(k)];
      best = std::min(best, rotation_angle_between(p.R, truth.R) * 1e3 + (p.t - truth.t).norm());
      EXPECT_LT((p.R.transpose() * p.R - Mat3::Identity()).norm(), 1e-9);
      EXPECT_NEAR(p.R.determinant(), 1.0, 1e-9);
    }
    EXPECT_LT(best, 1e-5) << "pose " << i;
    worst_rank = std::max(worst_rank, sols.count);
  }
  EXPECT_GE(worst_rank, 2);  // the beacon's triangles do have several solutions
}

TEST(P3P, ReturnsEveryRealSolution) {
  // Random general configurations (not only the beacon): the solver's set of
  // depth triples must equal the dense-scan reference's.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Braced initialisation draws left to right on every compiler.
  const auto draw3 = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  int with_four = 0, compared = 0;
  for (int i = 0; i < 300; ++i) {
    std::array<Vec3, 3> x, y;
    const Vec3 w = draw3();
    const Vec3 t = draw3() + Vec3(0.0, 0.0, 4.0);
    const Pose truth{exp_so3(w * 2.0), t};
    for (auto& p : x) p = draw3();
    for (size_t k = 0; k < 3; ++k) y[k] = truth.apply(x[k]).normalized();
    const auto ref = reference_depths(y, x);
    const auto sols = p3p_lambda_twist(y, x);
    // Skip near-tangent cases where the scan can miss a double root.
    bool near_double = false;
    for (size_t a = 0; a < ref.size(); ++a)
      for (size_t b = a + 1; b < ref.size(); ++b) near_double |= (ref[a] - ref[b]).norm() < 1e-3;
    if (near_double) continue;
    ++compared;
    // Every returned solution is exact; the scan may miss a root where two
    // branches meet at its edge, so ours may hold more, never fewer.
    for (int k = 0; k < sols.count; ++k) {
      const auto& p = sols.poses[static_cast<size_t>(k)];
      for (size_t j = 0; j < 3; ++j)
        EXPECT_LT((p.apply(x[j]).normalized() - y[j]).norm(), 1e-7) << "configuration " << i;
    }
    ASSERT_GE(sols.count, static_cast<int>(ref.size())) << "configuration " << i;
    with_four += sols.count == 4;
    for (const auto& L : ref) {
      bool found = false;
      for (int k = 0; k < sols.count; ++k) {
        const auto& p = sols.poses[static_cast<size_t>(k)];
        Eigen::Vector3d depths;
        for (int j = 0; j < 3; ++j) depths[j] = p.apply(x[static_cast<size_t>(j)]).norm();
        found |= (depths - L).norm() < 1e-5 * (1 + L.norm());
      }
      EXPECT_TRUE(found) << "configuration " << i;
    }
  }
  EXPECT_GT(compared, 250);
  EXPECT_GT(with_four, 0);
}

TEST(P3P, DegenerateInputGivesNoSolution) {
  std::array<Vec3, 3> x{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};  // collinear
  std::array<Vec3, 3> y{Vec3(0, 0, 1), Vec3(0.1, 0, 1).normalized(), Vec3(0.2, 0, 1).normalized()};
  EXPECT_EQ(p3p_lambda_twist(y, x).count, 0);
}
