// Levenberg-Marquardt on the reprojection error over SE(3).
//
// Residual per dot i: r_i = project(R * X_i + t) - u_i (pixels). The update
// is a left perturbation R <- exp([w]x) R, t <- t + dt with the analytic
// Jacobian d r_i / d(w, dt) = d project/dP * [ -[R X_i]x | I ].
#pragma once

#include <span>

#include <Eigen/Core>

#include "earshot/tracker/correspondence.hpp"

namespace earshot::tracker {

struct LmOptions {
  int max_iterations = 20;
  double initial_lambda = 1e-3;
  double step_tolerance = 1e-9;      ///< stop when |delta| < this (rad / mm scale)
  double cost_tolerance = 1e-12;     ///< relative cost decrease to stop
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
  double cost = 0.0;  ///< 0.5 * sum |r_i|^2, pixels^2
  int iterations = 0;
  bool converged = false;
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
