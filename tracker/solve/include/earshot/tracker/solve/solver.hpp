// The common interface of the pose solvers (one per file):
//   thesis_solver.hpp  the 2009 thesis method, kept as the reference
//   lm_solver.hpp      Levenberg-Marquardt from the previous pose or from P3P
// A solver gets labelled dots of one frame and, when the tracker has one, a
// predicted pose to start from. It returns a pose or nothing (cannot solve).
#pragma once

#include <memory>
#include <optional>
#include <string_view>

#include "earshot/tracker/core/correspondence.hpp"

namespace earshot::tracker {

struct SolveRequest {
  std::span<const Correspondence> dots;
  const Pose* prior = nullptr;  ///< predicted pose for this frame, if any
};

class PoseSolver {
 public:
  virtual ~PoseSolver() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// Pose for this frame, or nullopt when the dots do not determine one.
  virtual std::optional<Pose> solve(const SolveRequest& req) = 0;
  /// Forget any state carried between frames (after a loss).
  virtual void reset() {}
  /// Frames of delay the solver itself adds (the thesis median filter adds 2).
  [[nodiscard]] virtual int latency_frames() const { return 0; }
};

enum class SolverMethod { thesis, lm };

[[nodiscard]] std::optional<SolverMethod> solver_method_from(std::string_view name);
[[nodiscard]] std::unique_ptr<PoseSolver> make_solver(SolverMethod m, const Camera& cam,
                                                      const LedModel& model);

}  // namespace earshot::tracker
