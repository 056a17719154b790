#include "earshot/tracker/solve/thesis_solver.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace earshot::tracker {
namespace {

constexpr std::array<std::array<int, 2>, 6> kPairs{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return (n % 2) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

ThesisSolver::ThesisSolver(const Camera& cam, const LedModel& model, bool median_filter)
    : cam_(cam), model_(model), median_(median_filter) {}

void ThesisSolver::reset() {
  have_prev_ = false;
  history_.clear();
}

std::array<double, 4> ThesisSolver::solve_distances(const std::array<Vec3, 4>& b,
                                                    const std::array<double, 4>& r0) const {
  // Eq. 47: cosines of the angles between the rays; eq. 48: law of cosines.
  std::array<double, 6> cosines{}, d2{};
  for (size_t k = 0; k < kPairs.size(); ++k) {
    const auto i = static_cast<size_t>(kPairs[k][0]), j = static_cast<size_t>(kPairs[k][1]);
    cosines[k] = b[i].dot(b[j]);
    d2[k] = (model_.leds_mm[i] - model_.leds_mm[j]).squaredNorm();
  }
  Eigen::Vector4d r(r0[0], r0[1], r0[2], r0[3]);
  for (int it = 0; it < 50; ++it) {
    Eigen::Matrix<double, 6, 4> J = Eigen::Matrix<double, 6, 4>::Zero();
    Eigen::Matrix<double, 6, 1> f;
    for (size_t k = 0; k < kPairs.size(); ++k) {
      const int i = kPairs[k][0], j = kPairs[k][1];
      f[static_cast<long>(k)] = r[i] * r[i] + r[j] * r[j] - 2.0 * r[i] * r[j] * cosines[k] - d2[k];
      J(static_cast<long>(k), i) = 2.0 * r[i] - 2.0 * r[j] * cosines[k];
      J(static_cast<long>(k), j) = 2.0 * r[j] - 2.0 * r[i] * cosines[k];
    }
    // Gauss-Newton step: least squares J * step = -f (normal equations).
    const Eigen::Vector4d step = (J.transpose() * J).ldlt().solve(-J.transpose() * f);
    if (!step.allFinite()) break;
    r += step;
    if (step.norm() < 1e-7 * (1.0 + r.norm())) break;
  }
  return {r[0], r[1], r[2], r[3]};
}

Pose absolute_orientation(const std::array<Vec3, 4>& model_pts, const std::array<Vec3, 4>& measured) {
  Vec3 mc = Vec3::Zero(), pc = Vec3::Zero();
  for (size_t i = 0; i < 4; ++i) {
    mc += model_pts[i] / 4.0;
    pc += measured[i] / 4.0;
  }
  Mat3 H = Mat3::Zero();  // cross-covariance of the centred sets (eq. 54-55)
  for (size_t i = 0; i < 4; ++i) H += (model_pts[i] - mc) * (measured[i] - pc).transpose();
  const Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) D(2, 2) = -1.0;
  Pose p;
  p.R = svd.matrixV() * D * svd.matrixU().transpose();
  p.t = pc - p.R * mc;  // eq. 56
  return p;
}

std::optional<Pose> ThesisSolver::solve(const SolveRequest& req) {
  if (req.dots.size() != 4) return std::nullopt;  // the thesis needs all four
  std::array<Vec3, 4> bearings;
  std::array<bool, 4> seen{};
  for (const auto& d : req.dots) {
    const auto i = static_cast<size_t>(d.led);
    bearings[i] = cam_.bearing(d.pixel);
    seen[i] = true;
  }
  if (!std::all_of(seen.begin(), seen.end(), [](bool s) { return s; })) return std::nullopt;

  // The thesis starts from the previous result (fig. 77); the first frame
  // starts from a guess at one metre.
  const std::array<double, 4> r0 = have_prev_ ? r_prev_ : std::array<double, 4>{1000, 1000, 1000, 1000};
  std::array<double, 4> r = solve_distances(bearings, r0);
  const bool ok = std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v) && v > 0.0; });
  if (!ok) {
    reset();
    return std::nullopt;
  }
  r_prev_ = r;
  have_prev_ = true;

  if (median_) {  // median of 5 on the distances (section 3.2.9)
    history_.push_back(r);
    if (history_.size() > 5) history_.pop_front();
    for (size_t i = 0; i < 4; ++i) {
      std::vector<double> v;
      v.reserve(history_.size());
      for (const auto& h : history_) v.push_back(h[i]);
      r[i] = median_of(std::move(v));
    }
  }
  std::array<Vec3, 4> pts;  // eq. 49: points along the rays
  for (size_t i = 0; i < 4; ++i) pts[i] = r[i] * bearings[i];
  Pose p = absolute_orientation(model_.leds_mm, pts);
  if (!p.finite()) return std::nullopt;
  return p;
}

}  // namespace earshot::tracker
