// Levenberg-Marquardt on the reprojection error over SE(3).
//
// Residual per dot i: r_i = project(R * X_i + t) - u_i (pixels). The update
// is a left perturbation R <- exp([w]x) R, t <- t + dt with the analytic
// Jacobian d r_i / d(w, dt) = d project/dP * [ -[R X_i]x | I ].
#pragma once

#include <span>

#include <Eigen/Core>

#include "earshot/tracker/core/correspondence.hpp"

namespace earshot::tracker {

struct LmOptions {
  int max_iterations = 20;
  double initial_lambda = 1e-3;
  /// Stop once a step moves the dots by less than this (RMS over the dots,
  /// predicted from J: |J delta| / sqrt(n)), pixels; the step is taken.
  /// Convergence is quadratic, so the pose is then exact to far below any
  /// camera's noise (integer pixels: 0.29 px RMS); 1e-4 px keeps the
  /// noise-free tests exact to 1e-5 mm. Replaces a fixed count with tiny
  /// rad/mm tolerances, which ran 4-8 iterations a frame: from the
  /// tracker's prediction most solves now take two or three.
  double step_tolerance_px = 1e-4;
};

/// A Gaussian prior on the pose (e.g. the tracker's prediction), weighed
/// against pixel residuals of standard deviation `pixel_sigma`. With three
/// dots the reprojection alone fits every nearby pose equally; the prior
/// keeps the weakly determined directions where the motion says they are.
struct PosePrior {
  Pose pose;
  double rotation_sigma_rad = 0.02;
  double translation_sigma_mm = 5.0;
  double pixel_sigma = 0.3;
};

struct LmResult {
  Pose pose;
  /// 0.5 * sum |r_i|^2 (pixels^2, prior included) at the last pose evaluated:
  /// the final step, under step_tolerance_px, is taken without evaluating
  /// (it lowers the cost by less than n * step_tolerance_px^2 / 2).
  double cost = 0.0;
  int iterations = 0;
  bool converged = false;
  /// J^T J of the reprojection residuals alone (no prior) at the last pose
  /// evaluated: the pose's information per unit pixel variance, for
  /// pose_covariance_from_jtj (eskf.hpp) without differentiating again.
  Eigen::Matrix<double, 6, 6> jtj = Eigen::Matrix<double, 6, 6>::Zero();
};

/// Refines `initial` to the least-squares pose. Needs >= 3 correspondences.
[[nodiscard]] LmResult refine_pose_lm(const Pose& initial, std::span<const Correspondence> dots,
                                      const Camera& cam, const LedModel& model,
                                      const LmOptions& opt = {}, const PosePrior* prior = nullptr);

/// The 2x6 analytic Jacobian of one dot's residual with respect to (w, dt);
/// exposed so tests can compare it with finite differences.
[[nodiscard]] Eigen::Matrix<double, 2, 6> reprojection_jacobian(const Pose& pose, const Vec3& led,
                                                                const Camera& cam);

}  // namespace earshot::tracker
