#pragma once
// solveCeres(): the parametric boundary-value problem by an augmented-Lagrangian loop around
// Ceres 2.1. Each inner solve minimises, over q with t_f >= 1e-3 s,
//   1/2 |r(q)|^2 = J(q) + 1/2 mu |c(q) + lambda / mu|^2,
//   r0 = sqrt(2 J),   r_c = sqrt(mu) (c + lambda / mu)   (J > 0 since J >= t_f)
// by a trust-region method (Levenberg-Marquardt, dense QR) with the analytic Jacobian from the
// model's forward sensitivities (d r0 / dq = g / r0, d r_c / dq = sqrt(mu) A). After each inner
// solve lambda += mu c, and mu *= 10 unless |c| fell by at least 4x.
//
// The vehicle limits (path constraints) are NOT enforced by this back-end: its solution is
// only checked against them afterwards, by whoever calls it.
//
// Not thread-safe with respect to the model (one model per thread).

#include <Eigen/Core>
#include <atomic>
#include <optional>

#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp {

/// Settings of the Ceres back-end.
struct CeresOptions {
  ConvergenceCriteria criteria;
  int max_iterations = 100;       ///< budget of Ceres (inner) iterations over all outer iterations
  int max_outer_iterations = 20;  ///< multiplier updates, >= 1
  std::optional<double> time_limit_s;  ///< wall clock [s]; absent = none
  /// Set from outside to stop (SIGINT; may be null): the solve ends at its next check as at
  /// its time limit (time_limit_reached), its reason saying it was stopped.
  const std::atomic<bool>* stop = nullptr;
  double initial_penalty = 10.0;  ///< first mu, > 0
};

/// Solves the problem of `model` from q0 (without path constraints, see above). Returns method
/// "ceres"; status kConverged when the terminal errors are within options.criteria and
/// |g + A' lambda|_inf <= criteria.lagrangian_gradient after a multiplier update;
/// kMaxIterations when the iteration budget, max_outer_iterations or the time limit runs out;
/// kDiverged when an inner solve fails or q0 cannot be integrated; kError for a q0 of the
/// wrong size or invalid options. iterations counts Ceres iterations; history holds one record
/// per outer iteration (record 0: q0; step is NaN). lambda: multipliers of c (Lagrangian
/// J + lambda' c). Never throws.
SolveResult solveCeres(ParametricTrajectoryModel& model, const Eigen::VectorXd& q0,
                       const CeresOptions& options);

}  // namespace terratraj::ocp
