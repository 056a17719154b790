#include "earshot/tracker/solve/lm_refine.hpp"

#include <cmath>

#include "earshot/tracker/solve/small_cholesky.hpp"

namespace earshot::tracker {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// Damping at or below which an LM step is the Gauss-Newton step to within
/// 0.1 % (the default initial lambda: untouched by rejections).
constexpr double kUndampedLambda = 1e-3;

/// The problem linearised at one pose: cost, J^T J and J^T r.
struct Linearised {
  double cost = 0.0;  ///< 0.5 * sum of squared residuals, prior included
  Mat6 jtj_dots;      ///< J^T J of the reprojection residuals alone (lower triangle)
  Mat6 H;             ///< J^T J with the prior's (lower triangle)
  Vec6 g;             ///< J^T r
};

/// One pass over the dots: each is projected once and its residual and
/// Jacobian (lm_refine.hpp) come from the same numbers. False when a point
/// falls behind the camera.
bool linearise(const Pose& p, std::span<const Correspondence> dots, const Camera& cam, const LedModel& model,
               const PosePrior* prior, Linearised& out) {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double c = 0.0;
  for (const auto& d : dots) {
    const Vec3 RX = p.R * model.leds_mm[static_cast<size_t>(d.led)];
    const Vec3 P = RX + p.t;
    if (!(P.z() > 1e-6)) return false;
    const double iz = 1.0 / P.z();
    const double x = P.x() * iz, y = P.y() * iz;
    const Vec2 r(cam.fx * x + cam.cx - d.pixel.x(), cam.fy * y + cam.cy - d.pixel.y());
    // Rows of d project / dP; the rotation columns are (R X) x row, i.e.
    // row^T * -[R X]x.
    const Vec3 a(cam.fx * iz, 0.0, -cam.fx * x * iz);
    const Vec3 b(0.0, cam.fy * iz, -cam.fy * y * iz);
    Vec6 ja, jb;  // the two rows of J
    ja << RX.cross(a), a;
    jb << RX.cross(b), b;
    // J^T J's lower triangle only (all the Cholesky reads): 21 entries.
#pragma GCC unroll 6
    for (int k = 0; k < 6; ++k)
#pragma GCC unroll 6
      for (int i = k; i < 6; ++i) H(i, k) += ja(i) * ja(k) + jb(i) * jb(k);
    g += r.x() * ja + r.y() * jb;
    c += r.squaredNorm();
  }
  out.jtj_dots = H;
  if (prior) {  // prior residuals; d log(exp(w) R Rp^T)/dw ~ I near the prior
    const double wr = prior->pixel_sigma / prior->rotation_sigma_rad;
    const double wt = prior->pixel_sigma / prior->translation_sigma_mm;
    const Vec3 er = log_so3(p.R * prior->pose.R.transpose());
    const Vec3 et = p.t - prior->pose.t;
    H.diagonal().head<3>().array() += wr * wr;
    H.diagonal().tail<3>().array() += wt * wt;
    g.head<3>() += wr * wr * er;
    g.tail<3>() += wt * wt * et;
    c += wr * wr * er.squaredNorm() + wt * wt * et.squaredNorm();
  }
  out.cost = 0.5 * c;
  out.H = H;
  out.g = g;
  return true;
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
  Linearised cur;
  if (!linearise(initial, dots, cam, model, prior, cur)) {
    res.cost = INFINITY;
    return res;
  }
  res.cost = cur.cost;
  res.jtj = cur.jtj_dots;
  if (dots.size() < 3) {
    res.jtj.triangularView<Eigen::StrictlyUpper>() = res.jtj.transpose();
    return res;
  }

  // A step is small when it moves the dots by under the tolerance: its
  // predicted change of the residuals, delta^T H delta, against n tol^2.
  const double small2 = static_cast<double>(dots.size()) * opt.step_tolerance_px * opt.step_tolerance_px;
  double lambda = opt.initial_lambda;
  Linearised next;
  for (int it = 0; it < opt.max_iterations && !res.converged; ++it) {
    res.iterations = it + 1;
    bool improved = false;
    while (lambda < 1e12) {
      Mat6 A = cur.H;
      detail::Cholesky<6> L;
      A.diagonal() += lambda * (cur.H.diagonal().array() + 1e-12).matrix();
      Vec6 delta = Vec6::Constant(NAN);
      if (detail::cholesky<6>(A, L)) delta = -detail::cholesky_solve<6>(L, cur.g);
      if (!delta.allFinite()) {  // not positive definite (or not a number): damp harder
        lambda *= 10.0;
        continue;
      }
      const Pose cand{exp_so3(delta.head<3>()) * res.pose.R, res.pose.t + delta.tail<3>()};
      if (lambda <= kUndampedLambda && delta.dot(cur.H.selfadjointView<Eigen::Lower>() * delta) <= small2) {
        // Converged: take the last small step without evaluating it. Only
        // when the damping is negligible: a step made small by a large
        // lambda (after rejected steps) says nothing about the minimum.
        res.pose = cand;
        res.converged = true;
        improved = true;
        break;
      }
      if (linearise(cand, dots, cam, model, prior, next) && next.cost <= cur.cost) {
        res.pose = cand;
        std::swap(cur, next);
        res.cost = cur.cost;
        res.jtj = cur.jtj_dots;
        lambda = std::max(lambda * 0.1, 1e-12);
        improved = true;
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) {
      res.converged = true;  // no step lowers the cost: a minimum to precision
      break;
    }
  }
  res.jtj.triangularView<Eigen::StrictlyUpper>() = res.jtj.transpose();
  // Keep R exactly orthonormal after many small multiplications.
  const Quat q(res.pose.R);
  res.pose.R = q.normalized().toRotationMatrix();
  return res;
}

}  // namespace earshot::tracker
