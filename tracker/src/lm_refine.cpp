#include "earshot/tracker/lm_refine.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace earshot::tracker {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// 0.5 * sum of squared residuals; infinity when a point falls behind the camera.
double cost_of(const Pose& p, std::span<const Correspondence> dots, const Camera& cam,
               const LedModel& model, const PosePrior* prior) {
  double c = 0.0;
  if (prior) {
    const double wr = prior->pixel_sigma / prior->rotation_sigma_rad;
    const double wt = prior->pixel_sigma / prior->translation_sigma_mm;
    c += (wr * log_so3(p.R * prior->pose.R.transpose())).squaredNorm();
    c += (wt * (p.t - prior->pose.t)).squaredNorm();
  }
  for (const auto& d : dots) {
    const Vec3 P = p.apply(model.leds_mm[static_cast<size_t>(d.led)]);
    if (P.z() <= 1e-6) return INFINITY;
    c += (cam.project(P) - d.pixel).squaredNorm();
  }
  return 0.5 * c;
}

}  // namespace

Eigen::Matrix<double, 2, 6> reprojection_jacobian(const Pose& pose, const Vec3& led,
                                                  const Camera& cam) {
  const Vec3 RX = pose.R * led;
  const Vec3 P = RX + pose.t;
  const double iz = 1.0 / P.z(), iz2 = iz * iz;
  Eigen::Matrix<double, 2, 3> dpi;
  dpi << cam.fx * iz, 0.0, -cam.fx * P.x() * iz2, 0.0, cam.fy * iz, -cam.fy * P.y() * iz2;
  Eigen::Matrix<double, 2, 6> J;
  J.leftCols<3>() = -dpi * skew(RX);
  J.rightCols<3>() = dpi;
  return J;
}

LmResult refine_pose_lm(const Pose& initial, std::span<const Correspondence> dots,
                        const Camera& cam, const LedModel& model, const LmOptions& opt,
                        const PosePrior* prior) {
  LmResult res;
  res.pose = initial;
  res.cost = cost_of(initial, dots, cam, model, prior);
  if (dots.size() < 3 || !std::isfinite(res.cost)) return res;

  double lambda = opt.initial_lambda;
  for (int it = 0; it < opt.max_iterations; ++it) {
    res.iterations = it + 1;
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    for (const auto& d : dots) {
      const Vec3& X = model.leds_mm[static_cast<size_t>(d.led)];
      const auto J = reprojection_jacobian(res.pose, X, cam);
      const Vec2 r = cam.project(res.pose.apply(X)) - d.pixel;
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * r;
    }
    if (prior) {  // prior residuals; d log(exp(w) R Rp^T)/dw ~ I near the prior
      const double wr = prior->pixel_sigma / prior->rotation_sigma_rad;
      const double wt = prior->pixel_sigma / prior->translation_sigma_mm;
      H.diagonal().head<3>().array() += wr * wr;
      H.diagonal().tail<3>().array() += wt * wt;
      g.head<3>() += wr * wr * log_so3(res.pose.R * prior->pose.R.transpose());
      g.tail<3>() += wt * wt * (res.pose.t - prior->pose.t);
    }
    bool improved = false;
    Vec6 delta = Vec6::Zero();
    while (lambda < 1e12) {
      Mat6 A = H;
      A.diagonal() += lambda * (H.diagonal().array() + 1e-12).matrix();
      delta = -A.ldlt().solve(g);
      if (!delta.allFinite()) {
        lambda *= 10.0;
        continue;
      }
      const Pose cand{exp_so3(delta.head<3>()) * res.pose.R, res.pose.t + delta.tail<3>()};
      const double c = cost_of(cand, dots, cam, model, prior);
      if (c <= res.cost) {
        const double old = res.cost;
        res.pose = cand;
        res.cost = c;
        lambda = std::max(lambda * 0.1, 1e-12);
        improved = true;
        if (old - c <= opt.cost_tolerance * (old + 1e-30)) res.converged = true;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) {
      res.converged = true;  // no step lowers the cost: a minimum to precision
      break;
    }
    const double step = delta.head<3>().norm() + delta.tail<3>().norm() / (1.0 + res.pose.t.norm());
    if (res.converged || step < opt.step_tolerance) {
      res.converged = true;
      break;
    }
  }
  // Keep R exactly orthonormal after many small multiplications.
  const Quat q(res.pose.R);
  res.pose.R = q.normalized().toRotationMatrix();
  return res;
}

}  // namespace earshot::tracker
