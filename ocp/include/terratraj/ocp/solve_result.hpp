#pragma once
// SolveResult: what every boundary-value solver returns (the contract's solve report, before
// the independent re-simulation adds its figures).

#include <Eigen/Core>
#include <string>
#include <vector>

namespace terratraj::ocp {

/// How a solve ended (the contract's `status`).
enum class SolveStatus {
  kConverged,      ///< terminal errors and the Lagrangian gradient within tolerance
  kMaxIterations,  ///< max_iterations (or the time limit) reached first
  kInfeasible,     ///< no trajectory of this form meets the constraints (reason says which)
  kDiverged,       ///< the iteration failed (off the map, t_f -> 0, NaN, no descent)
  kError,          ///< the problem could not be set up
};

/// The contract's name ("converged", "max_iterations", ...).
const char* solveStatusName(SolveStatus status);

/// When a solve counts as converged (004_... 3.5).
struct ConvergenceCriteria {
  double position_m = 1e-3;           ///< terminal position error [m]
  double heading_rad = 1e-3;          ///< terminal heading error [rad]
  double lagrangian_gradient = 1e-1;  ///< infinity norm of dJ/dq + lambda' dc/dq
};

/// One iteration of a solver.
struct IterationRecord {
  int iteration = 0;
  double terminal_error = 0.0;       ///< position error [m]
  double heading_error = 0.0;        ///< |heading error| [rad]
  double cost = 0.0;                 ///< J [s]
  double lagrangian_gradient = 0.0;  ///< stationarity (NaN where a solver does not compute it)
  double step = 0.0;                 ///< step length accepted (line-search fraction)
};

/// The outcome of a solver.
struct SolveResult {
  SolveStatus status = SolveStatus::kError;
  std::string reason;  ///< why, for anything but kConverged
  std::string method;  ///< "newton", "newton_fd", "ipopt", "ceres"
  int iterations = 0;
  std::vector<IterationRecord> history;
  double solve_time_ms = 0.0;
  Eigen::VectorXd q;                                         ///< final control unknowns
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();          ///< final multipliers
  double cost = 0.0;                                         ///< J at q (solver's own figure)
  Eigen::Vector3d terminal_error = Eigen::Vector3d::Zero();  ///< c(q) (solver's own figure)
  long integrations = 0;                                     ///< trajectory integrations used
  /// The solver stopped on its time limit (status not kConverged): what it returns is an
  /// unfinished iterate.
  bool time_limit_reached = false;
};

}  // namespace terratraj::ocp
