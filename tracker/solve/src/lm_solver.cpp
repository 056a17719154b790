#include "earshot/tracker/solve/lm_solver.hpp"

#include <limits>

#include "earshot/tracker/solve/p3p.hpp"

namespace earshot::tracker {

LmSolver::LmSolver(const Camera& cam, const LedModel& model, LmOptions opt)
    : cam_(cam), model_(model), opt_(opt) {}

std::optional<Pose> p3p_initial_pose(std::span<const Correspondence> dots, const Camera& cam,
                                     const LedModel& model, const Pose* prior) {
  if (dots.size() < 3) return std::nullopt;
  std::array<Vec3, 3> bearings, points;
  for (size_t i = 0; i < 3; ++i) {
    bearings[i] = cam.bearing(dots[i].pixel);
    points[i] = model.leds_mm[static_cast<size_t>(dots[i].led)];
  }
  const P3PSolutions sols = p3p_lambda_twist(bearings, points);
  double best = std::numeric_limits<double>::infinity();
  std::optional<Pose> out;
  for (int k = 0; k < sols.count; ++k) {
    const Pose& p = sols.poses[static_cast<size_t>(k)];
    double score = 0.0;
    if (prior) {
      // Distance to the prediction: rotation angle plus translation scaled
      // so that 100 mm weighs like one radian.
      score = rotation_angle_between(p.R, prior->R) + (p.t - prior->t).norm() / 100.0;
    } else if (dots.size() >= 4) {
      score = rms_reprojection_error(p, dots, cam, model);
    } else {
      return std::nullopt;  // three dots and no prior: the solutions are indistinguishable
    }
    if (score < best) {
      best = score;
      out = p;
    }
  }
  return out;
}

std::optional<Pose> LmSolver::solve(const SolveRequest& req) {
  if (req.dots.size() < 3) return std::nullopt;
  std::optional<Pose> start;
  if (req.prior && req.dots.size() == 3) {
    // Three dots fit every P3P solution exactly: take the one nearest the prior.
    start = p3p_initial_pose(req.dots, cam_, model_, req.prior);
  }
  if (!start && req.prior) start = *req.prior;
  if (!start) start = p3p_initial_pose(req.dots, cam_, model_, nullptr);
  if (!start) return std::nullopt;
  // Three dots determine the pose only up to noise-amplifying directions:
  // weigh in the prediction as a prior (a MAP estimate instead of ML).
  std::optional<PosePrior> prior;
  if (req.prior && req.dots.size() == 3) prior = PosePrior{*req.prior};
  const LmResult r = refine_pose_lm(*start, req.dots, cam_, model_, opt_, prior ? &*prior : nullptr);
  if (!r.pose.finite() || !std::isfinite(r.cost) || r.pose.t.z() <= 0.0) return std::nullopt;
  return r.pose;
}

}  // namespace earshot::tracker
