#pragma once
// solveIpopt(): the parametric boundary-value problem as a small dense NLP for Ipopt 3.11
// (interior point, MUMPS, limited-memory quasi-Newton Hessian):
//   min_q  J(q)
//   s.t.   c(q) = 0                               (terminal x, y, heading; 3 rows)
//          g(p(tau_i; q)) <= 0, i = 0..N-1        (PathConstraints rows at tau_i = i / (N - 1))
//          1e-3 s <= t_f <= max_final_time_s
// with exact first derivatives from the model's forward sensitivities. Each new q costs one
// integration with sensitivities (evaluateWithPath when path constraints are imposed, else
// evaluate); Ipopt's repeated calls at the same q are served from a cache.
//
// Thread safety: Ipopt 3.11 (with the sequential MUMPS of Debian) is NOT thread-safe; run at
// most one solveIpopt() per process at a time. The model is not thread-safe either.

#include <Eigen/Core>
#include <atomic>
#include <optional>

#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/path_constraints.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp {

/// Settings of the Ipopt back-end.
struct IpoptOptions {
  /// Convergence: the terminal errors are checked on the final q; position_m and heading_rad
  /// also set Ipopt's constr_viol_tol (a tenth of the smaller), lagrangian_gradient its
  /// dual_inf_tol.
  ConvergenceCriteria criteria;
  int max_iterations = 100;  ///< Ipopt's max_iter, >= 0
  std::optional<double>
      time_limit_s;  ///< wall clock [s] (also Ipopt's max_cpu_time); absent = none
  /// Set from outside to stop (SIGINT; may be null): the solve ends at its next check as at
  /// its time limit (time_limit_reached), its reason saying it was stopped.
  const std::atomic<bool>* stop = nullptr;
  int path_points = 41;  ///< points tau_i where path constraints hold, >= 2
  /// Upper bound of t_f [s] (absent: none). A local solve from a seed has no use for a final
  /// time far beyond the seed's; without a bound the free-speed polynomials can wander to
  /// hundreds of seconds, where each integration is slow.
  std::optional<double> max_final_time_s;
  bool path_constraints = true;  ///< false: terminal equalities only
  int print_level = 0;           ///< Ipopt's print_level, 0 (silent) to 12
  /// Ipopt's own test is about 100 times tighter than `criteria`: past this many iterations a
  /// solve stops at the first iterate that meets the criteria (it wanders there), >= 0.
  int wandering_iterations = 100;
};

/// Solves the problem of `model` from q0 with Ipopt. `constraints` (may be null: none) are the
/// vehicle limits imposed at options.path_points points when options.path_constraints is set.
/// Returns method "ipopt"; status kConverged when Ipopt reports success (or an acceptable
/// level) and the final terminal errors are within options.criteria, or when Ipopt ends
/// otherwise (or past options.wandering_iterations) after an iterate met the criteria (terminal
/// errors, path rows, Ipopt's optimality error within lagrangian_gradient): the lowest-cost
/// such iterate is the answer; kMaxIterations for the
/// iteration or time limit; kInfeasible when Ipopt detects a locally infeasible problem;
/// kDiverged otherwise (including a q0 whose integration fails); kError for a q0 of the wrong
/// size or invalid options. history holds one record per Ipopt iteration (lagrangian_gradient
/// is Ipopt's scaled dual infeasibility inf_du, step its primal step size alpha_pr); lambda
/// holds the multipliers of the 3 terminal equalities (Lagrangian J + lambda' c + ...).
/// Never throws. Not thread-safe (see above).
SolveResult solveIpopt(ParametricTrajectoryModel& model, const PathConstraints* constraints,
                       const Eigen::VectorXd& q0, const IpoptOptions& options);

}  // namespace terratraj::ocp
