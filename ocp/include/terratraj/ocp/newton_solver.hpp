#pragma once
// Newton's method on the KKT system of 004_... eq. 7:
//   [ W  A' ] [ dq      ]   [ -g ]
//   [ A  0  ] [ lambda+ ] = [ -c ]
// with c the terminal error, A = dc/dq, g = dJ/dq and W the Hessian of the Lagrangian
// J + lambda' c. Derivatives from sensitivities or finite differences (eq. 10); W from
// finite differences (eq. 11, or of sensitivity gradients) or damped BFGS; globalised by a
// backtracking line search on the l1 merit J + nu |c|_1 with a second-order correction, and a
// fraction-to-boundary rule that keeps t_f positive.

#include <Eigen/Core>
#include <atomic>
#include <optional>

#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp {

/// How W is obtained.
enum class HessianApproximation {
  kFiniteDifference,  ///< recomputed every iteration (eq. 11, or of sensitivity gradients)
  kBfgs,              ///< damped BFGS (Powell), from the start's Hessian when given
};

/// Settings of the Newton iteration.
struct NewtonOptions {
  DerivativeMode derivatives = DerivativeMode::kSensitivity;
  HessianApproximation hessian = HessianApproximation::kBfgs;
  double hessian_step = 1e-5;  ///< finite-difference step for W
  bool line_search = true;     ///< false: full Newton steps (the paper's iteration)
  ConvergenceCriteria criteria;
  int max_iterations = 100;            ///< >= 1
  std::optional<double> time_limit_s;  ///< wall clock; absent = none
  /// Set from outside to stop (SIGINT; may be null): the solve ends at its next check as at
  /// its time limit (time_limit_reached), its reason saying it was stopped.
  const std::atomic<bool>* stop = nullptr;
  double min_final_time_s = 1e-3;  ///< t_f below this counts as a collapse [s]
};

/// Where the iteration starts.
struct NewtonStart {
  Eigen::VectorXd q;
  std::optional<Eigen::Vector3d> lambda;  ///< absent: least-squares multipliers (eq. 15)
  Eigen::MatrixXd hessian;                ///< BFGS's first W; empty: identity
};

/// Runs the iteration on `model` from `start`. Never throws; the status says how it ended and
/// `method` is copied into the result.
SolveResult solveNewton(ParametricTrajectoryModel& model, const NewtonStart& start,
                        const NewtonOptions& options, const char* method);

/// Least-squares multipliers lambda = -(A A')^-1 A g (004_... eq. 15).
Eigen::Vector3d leastSquaresMultipliers(const Eigen::MatrixXd& jacobian,
                                        const Eigen::VectorXd& gradient);

}  // namespace terratraj::ocp
