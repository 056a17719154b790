// Our solver: Levenberg-Marquardt on the reprojection error (lm_refine.hpp),
// started from the tracker's predicted pose, or, without one, from the best
// Lambda Twist P3P solution. Works with three or four labelled dots.
#pragma once

#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/solver.hpp"

namespace earshot::tracker {

class LmSolver final : public PoseSolver {
 public:
  LmSolver(const Camera& cam, const LedModel& model, LmOptions opt = {});

  [[nodiscard]] std::string_view name() const override { return "lm"; }
  std::optional<Pose> solve(const SolveRequest& req) override;

 private:
  Camera cam_;
  LedModel model_;
  LmOptions opt_;
};

/// Among the P3P solutions of three of the dots, the one closest to `prior`
/// (if given) or, with a fourth dot, the one that reprojects it best.
[[nodiscard]] std::optional<Pose> p3p_initial_pose(std::span<const Correspondence> dots,
                                                   const Camera& cam, const LedModel& model,
                                                   const Pose* prior);

}  // namespace earshot::tracker
