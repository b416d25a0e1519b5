#pragma once
// solveBoundaryValue(): the whole boundary-value solve of `terratraj solve` (004_...): the
// flat-ground initial guess, one of the solvers on the terrain, then an independent
// re-simulation that supplies the report's figures and decides the final status.

#include <atomic>
#include <optional>
#include <string>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/initial_guess.hpp"
#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::ocp {

/// The solvers over the parametric formulation.
enum class BoundaryValueMethod {
  kNewton,    ///< sensitivities, damped BFGS from the flat optimum's Hessian, line search
  kNewtonFd,  ///< the paper's: finite-difference Jacobian and Hessian (eqs. 10-11), RK4
  kIpopt,     ///< Ipopt with exact first derivatives and sampled path constraints
  kCeres,     ///< Ceres under an augmented-Lagrangian loop (limits not enforced)
};

/// "newton", "newton_fd", "ipopt", "ceres".
const char* boundaryValueMethodName(BoundaryValueMethod method);

/// Settings of a solve.
struct BoundaryValueOptions {
  BoundaryValueMethod method = BoundaryValueMethod::kNewton;
  ConvergenceCriteria criteria;
  int max_iterations = 100;            ///< solver iterations, >= 1
  std::optional<double> time_limit_s;  ///< wall clock of the solver; absent = none
  /// Set from outside to stop (SIGINT; may be null): the solve ends at its next check as at
  /// its time limit (time_limit_reached), its reason saying it was stopped.
  const std::atomic<bool>* stop = nullptr;
  /// Integration of the terrain stage (CVODES; newton_fd switches to fixed-step RK4 so that
  /// finite differences see a smooth map).
  models::IntegratorOptions integrator = [] {
    models::IntegratorOptions options;
    options.relative_tolerance = 1e-7;
    options.absolute_tolerance = 1e-9;
    return options;
  }();
  double newton_fd_step = 0.01;  ///< RK4 step of newton_fd [s]
  int path_points = 41;          ///< ipopt: points where path constraints are imposed, >= 2
  /// ipopt: when the check finds a limit broken between path points, the solve is repeated
  /// from its solution with twice as many points (2 n - 1), up to this many, >= path_points.
  int max_path_points = 321;
  /// ipopt: the Segway's slope speed and acceleration bounds are held times this, in (0, 1]:
  /// a margin for the look-ups between path points (the check judges by the look-ups).
  double segway_bound_scale = 0.99;
  /// ipopt: t_f at most this times the initial guess's t_f (0: unbounded), >= 1 or 0. A local
  /// solve has no use for a final time far beyond its seed's.
  double max_final_time_ratio = 5.0;
  VerificationOptions verification;
  /// Where the flat-ground initial guess starts (problem's ParametricControls layout, e.g.
  /// ocp::fitParametricControls of a global seed); empty: 004's heuristic.
  Eigen::VectorXd initial_q;
};

/// A solve and its verification.
struct BoundaryValueSolution {
  SolveStatus status = SolveStatus::kError;  ///< after verification
  std::string reason;                        ///< why, for anything but kConverged
  SolveResult solver;                        ///< the solver's own account
  InitialGuess initial_guess;
  VerifiedTrajectory verified;        ///< the re-simulation of solver.q (ok false if not possible)
  models::TrajectoryVerdict verdict;  ///< the independent check of verified.trajectory
  double total_time_ms = 0.0;         ///< initial guess + solver [ms]
  double verification_time_ms = 0.0;  ///< the re-simulation [ms]
  int path_points = 0;  ///< ipopt: path points of the last solve (0 for the other methods)
  /// The time limit ended the solve, or a further round with more path points that its
  /// verdict asked for: with more time the result may differ (else it would be the same).
  bool time_limit_reached = false;
};

/// Solves `problem` on `vehicle`; `map` (optional: no map rules without it) supplies the
/// lethal, no-data and off-map rules of the check. The solver aims at half the criteria's terminal
/// tolerances; the final status is the verdict (solution_verdict.hpp) on the re-simulated
/// trajectory as written: kConverged only when it ends within the criteria and every limit, table
/// and map rule holds at every sample (else kInfeasible or kDiverged, the rule named). Never
/// throws.
BoundaryValueSolution solveBoundaryValue(const models::TerrainFollowingModel& vehicle,
                                         const BoundaryValueProblem& problem,
                                         const BoundaryValueOptions& options,
                                         const terrain::ElevationMap* map = nullptr);

}  // namespace terratraj::ocp
