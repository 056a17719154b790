#include "earshot/tracker/solve/solver.hpp"

#include "earshot/tracker/solve/lm_solver.hpp"
#include "earshot/tracker/solve/thesis_solver.hpp"

namespace earshot::tracker {

std::optional<SolverMethod> solver_method_from(std::string_view name) {
  if (name == "thesis") return SolverMethod::thesis;
  if (name == "lm") return SolverMethod::lm;
  return std::nullopt;
}

std::unique_ptr<PoseSolver> make_solver(SolverMethod m, const Camera& cam, const LedModel& model) {
  switch (m) {
    case SolverMethod::thesis: return std::make_unique<ThesisSolver>(cam, model);
    case SolverMethod::lm: return std::make_unique<LmSolver>(cam, model);
  }
  return nullptr;
}

}  // namespace earshot::tracker
