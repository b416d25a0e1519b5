#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp {

const char* solveStatusName(SolveStatus status) {
  switch (status) {
    case SolveStatus::kConverged:
      return "converged";
    case SolveStatus::kMaxIterations:
      return "max_iterations";
    case SolveStatus::kInfeasible:
      return "infeasible";
    case SolveStatus::kDiverged:
      return "diverged";
    case SolveStatus::kError:
      return "error";
  }
  return "error";
}

}  // namespace terratraj::ocp
