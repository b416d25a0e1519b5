#pragma once
// Direct transcription (multiple shooting and collocation) solved with Ipopt: trajectories
// polynomial controls cannot express (bang-bang acceleration, a pitch limit active for a
// stretch, long paths around obstacles), with a free final time, path constraints at every
// point, a warm start from any trajectory and optional mesh refinement.
// docs/optimal-control.md, "Direct transcription", gives the formulation and the choices.

#include <Eigen/Core>
#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/iteration_divergence.hpp"
#include "terratraj/ocp/iteration_stall.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"
#include "terratraj/ocp/transcription_nlp.hpp"

namespace terratraj::ocp {

/// Second derivatives given to Ipopt.
enum class TranscriptionHessian {
  kExact,          ///< collocation: block-diagonal Lagrangian Hessian (transcription_nlp.hpp)
  kLimitedMemory,  ///< Ipopt's L-BFGS (the only choice for multiple shooting)
};

/// Variable and constraint scaling given to Ipopt.
enum class TranscriptionScaling {
  kUser,           ///< v, omega, v' by their limits, t_f by the guess's, defects as their states
  kGradientBased,  ///< Ipopt's own
  kNone,
};

/// How Ipopt's barrier parameter mu starts and falls.
enum class TranscriptionBarrier {
  /// Ipopt's adaptive strategy, from a first mu it computes: robust from a rough guess (a
  /// straight line, a Dubins word, a planner's wiggly first solution).
  kAdaptive,
  /// Monotone from DirectTranscriptionOptions::warm_mu_init: for a guess already close to a
  /// feasible, locally optimal solution (a near-optimal planner candidate, an earlier round's
  /// or a coarser mesh's solution), where the adaptive strategy first moves away from it. About
  /// half the iterations there; from a rough guess it can take several times more (measured
  /// in docs/benchmarks.md, "Refinement of a planner candidate").
  kWarm,
};

/// Re-solving with more intervals where the integration error between nodes is large.
struct MeshRefinementOptions {
  int max_rounds = 0;        ///< 0: no refinement
  double tolerance = 1e-3;   ///< local error of an interval [m and rad] (RK4 from its node)
  int max_intervals = 1000;  ///< never refine beyond this many intervals
};

/// How to transcribe and solve.
struct DirectTranscriptionOptions {
  TranscriptionScheme scheme = TranscriptionScheme::kHermiteSimpson;
  ShootingControls shooting_controls = ShootingControls::kPiecewiseLinear;
  /// Hermite-Simpson: piecewise-linear controls (TranscriptionLayout::linear_controls), so that
  /// |v'| <= a_max and |omega'| hold between the points too; refinement uses it.
  bool linear_controls = false;
  /// The curvature rows at a start or goal at rest (TranscriptionLayout::rest_curvature).
  bool rest_curvature = false;
  /// Collocation: v_max, v >= 0, omega_max and kappa_max on the whole of every interval, not
  /// only at its points (TranscriptionLayout::interval_bounds_final_time: for final times up
  /// to the guess's, at most twice the straight drive's), so the re-simulation finds no
  /// overshoot of them there.
  bool interval_bounds = true;
  int intervals = 40;  ///< N, >= 1
  /// The mesh's node times, normalised (0 = start, 1 = t_f; strictly increasing, intervals + 1
  /// of them); empty: `intervals` equal intervals. solveTranscription's rounds set it when they
  /// halve only the intervals their verification found too coarse (mesh_split.hpp).
  std::vector<double> mesh;
  /// Unset: exact for collocation (with the Segway too: the model takes the C1 versions of its
  /// look-ups), limited-memory for shooting. With the Segway, a solve that ends locally
  /// infeasible or at max_iterations (not at the time limit) is tried once more with
  /// limited-memory from the same start (the reason says so when that fails too).
  std::optional<TranscriptionHessian> hessian;
  TranscriptionScaling scaling = TranscriptionScaling::kUser;
  double min_final_time = 1e-2;  ///< lower bound of t_f [s], > 0
  double max_final_time = 1e4;   ///< upper bound of t_f [s]
  int max_iterations = 1000;     ///< Ipopt iterations per solve, >= 1
  /// x and y are bounded to the map's extent inset by this much [m], >= 0 (the vehicle's
  /// footprint must stay on the map for its attitude to exist).
  double map_margin = 0.5;
  std::optional<double> time_limit_s;  ///< wall clock for the whole solve [s]
  /// Set from outside to stop (SIGINT; may be null): the solve ends at its next check as at
  /// its time limit (time_limit_reached), its reason saying it was stopped.
  const std::atomic<bool>* stop = nullptr;
  double tolerance = 1e-6;             ///< Ipopt's tol (scaled KKT error)
  double constraint_tolerance = 1e-8;  ///< Ipopt's constr_viol_tol (unscaled) [state units]
  /// A solve cycling at a feasible, nearly stationary point (a kink of the terrain) stops
  /// there as converged (Ipopt status "User_Requested_Stop (stalled ...)"); window 0: never.
  StallAcceptance stall;
  /// A solve whose dual infeasibility stays above a threshold (1e10) for `window` (20)
  /// iterations in a row, or rises above `blow_up` (1e12) once, has blown up (diverging
  /// multipliers): it stops as kInfeasible, the reason says so (iteration_divergence.hpp);
  /// window 0: never.
  DivergenceStop divergence;
  TranscriptionBarrier barrier = TranscriptionBarrier::kAdaptive;
  double warm_mu_init = 1e-6;  ///< kWarm's first barrier parameter (scaled), > 0
  MeshRefinementOptions refinement;
  int print_level = 0;  ///< Ipopt's print_level (0: silent; 5: its iteration log on stdout)
  TranscriptionModelOptions model;  ///< control effort, Segway constraints, clearance
};

/// A path constraint active at the solution.
struct ActiveConstraint {
  int point = 0;
  double t = 0.0;           ///< [s]
  std::string name;         ///< the limit ("pitch_max", ...)
  double value = 0.0;       ///< g (<= 0; close to 0)
  double multiplier = 0.0;  ///< Ipopt's multiplier (> 0 when active)
};

/// One round of mesh refinement.
struct RefinementRound {
  int intervals = 0;
  double max_interval_error = 0.0;  ///< [m, rad]
  int iterations = 0;
};

/// The outcome.
struct TranscriptionSolution {
  SolveResult result;        ///< status, reason, iterations, history, time, cost
  std::string ipopt_status;  ///< Ipopt's own status of the last solve ("Solve_Succeeded", ...)
  TranscriptionScheme scheme = TranscriptionScheme::kHermiteSimpson;
  ShootingControls shooting_controls = ShootingControls::kPiecewiseLinear;
  std::vector<double> mesh;              ///< node times, normalised
  std::vector<double> times;             ///< point times [s]
  std::vector<PointVector> points;       ///< w at each point
  double final_time = 0.0;               ///< [s]
  Eigen::VectorXd multipliers;           ///< one per constraint row (TranscriptionNlp order)
  std::vector<ActiveConstraint> active;  ///< active path constraints, with multipliers
  double max_defect = 0.0;               ///< largest |defect| at the solution [state units]
  std::vector<RefinementRound> refinement;
  /// The controls v', omega' [m/s^2, rad/s^2] at time t [s] as the scheme interpolates them
  /// (piecewise constant / linear, quadratic on Hermite-Simpson intervals).
  Eigen::Vector2d controlsAt(double t) const;
  /// The solution as a guess (for warm starts).
  TranscriptionGuess asGuess() const;
};

/// Why the options cannot be used, or std::nullopt.
std::optional<std::string> validateTranscriptionOptions(const DirectTranscriptionOptions& options);

/// Solves `problem` on `vehicle` from `guess` (its first and last points are replaced by the
/// start and goal; it is interpolated onto the mesh). Never throws: bad input gives kError,
/// Ipopt's failures map to kInfeasible (infeasible problem, restoration failure, too few
/// degrees of freedom), kDiverged (diverging iterates, step failures, MUMPS errors, invalid
/// numbers), kMaxIterations (iteration or time limit), with Ipopt's status in `ipopt_status`.
/// Ipopt 3.11 is not thread-safe: one solve at a time per process.
TranscriptionSolution solveDirectTranscription(const models::TerrainFollowingModel& vehicle,
                                               const BoundaryValueProblem& problem,
                                               const TranscriptionGuess& guess,
                                               const DirectTranscriptionOptions& options = {});

/// Largest local integration error over each interval of `solution` (from each node's
/// state with the interpolated controls, compared with the next node) [m, rad]; one entry per
/// interval; std::nullopt when an interval cannot be integrated (RK4, 32 sub-steps).
std::optional<std::vector<double>> intervalErrors(const TranscriptionModel& model,
                                                  const TranscriptionSolution& solution);

}  // namespace terratraj::ocp
