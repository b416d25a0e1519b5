#pragma once
// CandidateRefiner: turns a planner's candidate (or any path: a full trajectory, x,y,heading or
// only x,y) into a locally optimal trajectory with the optimal-control core, and checks that
// the result stays in the candidate's homotopy class (docs/refinement.md).
//
// Pipeline for one candidate:
//   1. the candidate is validated (at least two distinct points, finite, on the map) and
//      completed: missing timing gets a feasible speed profile (ocp::guessFromPath), missing
//      attitude columns come from the vehicle model;
//   2. its figures are measured (cost, length, pitch, roll, the independent TrajectoryChecker,
//      its HomotopySignature over the reference frames);
//   3. the method is chosen (RefineMethod::kAuto: polynomial controls through Ipopt when they
//      suffice, collocation otherwise; the rule is chooseRefineMethod) and the problem solved
//      from the candidate (direct transcription: warm start from it, or from its shortcut path
//      when it is wiggly, one interval per interval_length_m, a clearance constraint from
//      impassable cells so that the optimiser cannot slide through an obstacle, margin and
//      corridor retries);
//   4. the result is re-simulated independently, re-checked by TrajectoryChecker, and its
//      signature compared with the candidate's.
// A refinement counts as converged only when the solver converged, the verdict passes on the
// re-simulated trajectory (the goal within the solver's tolerances, every limit, table and map
// rule at every row), the class is kept, and it is no worse than a feasible candidate.

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/clearance_map.hpp"

namespace terratraj::search {

/// How a candidate is refined.
enum class RefineMethod {
  kAuto,         ///< ipopt when polynomial controls suffice, else collocation (see below)
  kCollocation,  ///< Hermite-Simpson (or the configured scheme) warm-started from the candidate
  kShooting,     ///< multiple shooting warm-started from the candidate
  kNewton,       ///< polynomial controls by 004_...'s Newton: limits not enforced, only checked
  kIpopt,        ///< polynomial controls through Ipopt, limits enforced (sampled)
};
// The parametric methods (newton, ipopt) start from their own guess, not the candidate's shape:
// they suit short, open, simple candidates, where the candidate's class is the direct one.

/// "auto", "collocation", "shooting", "newton", "ipopt".
const char* refineMethodName(RefineMethod method);
/// Parses a method name; std::nullopt if it is not one.
std::optional<RefineMethod> parseRefineMethod(std::string_view name);
/// Every method name, in declaration order.
std::vector<std::string> refineMethodNames();

/// Settings of a CandidateRefiner.
struct RefinementOptions {
  RefineMethod method = RefineMethod::kAuto;
  /// Wall clock of one refine() [s], >= 0, absent = none: every solve, retry and the
  /// re-simulation share it (a solve gets what is left).
  std::optional<double> time_limit_s;
  /// A candidate whose first point is farther than this from the start, or whose last point is
  /// farther than this from the goal, is refused (kError) [m], > 0.
  double endpoint_tolerance_m = 0.5;
  /// A refinement is worse than its feasible candidate when its cost exceeds the candidate's
  /// (credited with its last point's distance to the exact goal at v_max) by more than this
  /// fraction, >= 0: the margins and the discretisation put the refinement's optimum a few
  /// tenths of a per cent above the true one, and the credit is optimistic.
  double worse_tolerance = 0.01;
  /// Set from outside to stop a refinement early (SIGINT): it ends with what it has.
  const std::atomic<bool>* stop = nullptr;
  /// Direct transcription: one interval per this much candidate length [m], > 0 ...
  double interval_length_m = 0.25;
  int min_intervals = 20;   ///< ... but at least this many, >= 1
  int max_intervals = 800;  ///< ... and at most this many, >= min_intervals
  /// For a candidate whose shortcut guess is used (a wiggly one), a first solve on a coarse mesh
  /// (one interval per this much length [m], > 0), whose solution (when it converges) starts
  /// the fine one; skipped when it would not halve the intervals.
  double coarse_interval_length_m = 1.0;
  /// Clearance kept from lethal and no-data cells [m], >= 0; lowered to half the candidate's
  /// own smallest clearance when that is less (a candidate through a narrow gap stays
  /// feasible); raised to half a cell (at most this) when the re-simulation clips a lethal cell.
  double min_clearance_m = 0.25;
  /// kAuto picks ipopt (polynomial controls) only for candidates at most this long [m] ...
  double parametric_max_length_m = 10.0;
  /// ... whose every sample is at least this far from impassable cells [m] ...
  double parametric_min_clearance_m = 3.0;
  /// ... and whose curvature changes sign at most this many times (a quartic yaw rate).
  int parametric_max_curvature_sign_changes = 2;
  /// Direct transcription settings (scheme, iterations, time limit, tolerances; the number of
  /// intervals and the clearance are set per candidate).
  ocp::DirectTranscriptionOptions transcription = [] {
    ocp::DirectTranscriptionOptions options;
    options.max_iterations = 500;
    options.linear_controls = true;
    return options;
  }();
  /// Direct transcription imposes the limits at its points only: it is solved with kappa_max,
  /// sigma_max, pitch_max and roll_max lowered by this fraction, in [0, 0.5), so that the
  /// re-simulated trajectory holds the true limits between the points too ...
  double limit_margin = 0.02;
  /// ... and with v_max and omega_max lowered by this fraction, in [0, 0.5) (the speed is
  /// quadratic between points; the overshoot measured at 0.25 m intervals is about 0.1 %).
  double speed_margin = 0.0005;
  /// A re-simulation that still breaks a limit (the verdict's 1e-3 relative) is
  /// solved again from its own solution, up to this many times, >= 0: with the clearance
  /// raised to half a cell if it clipped a lethal cell; else first with twice the intervals
  /// (within max_intervals), then with the speed margin x 4 and the others x 2 (at most 0.25).
  int margin_retries = 3;
  /// The parametric solvers' settings (newton, ipopt; the method is set per refinement), and
  /// the terminal tolerances and limit tolerance of every method.
  ocp::BoundaryValueOptions parametric;
  /// Sampling of the candidate's derived speed profile for an x,y path [m].
  double guess_spacing_m = 0.25;
  /// A converged refinement that left the candidate's class is solved again from the candidate
  /// inside a corridor: the cells within this distance of it [m], > 0 (0: no retry), the rest
  /// made impassable for the clearance constraint. A path in the corridor can only leave the
  /// class through an obstacle inside it.
  double corridor_radius_m = 1.0;
  /// The optimiser starts from the candidate's shortcut path (greedy straight segments that
  /// keep this clearance from impassable cells [m], > 0; 0: never) when that is shorter than
  /// shortcut_gain x the candidate's length and in the same class: loops and detours of a
  /// wiggly candidate cost iterations and can trap the optimiser.
  double shortcut_clearance_m = 0.35;
  double shortcut_gain = 0.95;  ///< in (0, 1]
};

/// Why the options cannot be used, or std::nullopt.
std::optional<std::string> validateRefinementOptions(const RefinementOptions& options);

/// The figures of one trajectory (a candidate or its refinement).
struct TrajectoryFigures {
  double cost = 0.0;        ///< the problem's cost functional, integrated over the samples [s]
  double duration_s = 0.0;  ///< [s]
  double length_m = 0.0;    ///< planar length [m]
  double max_abs_pitch = 0.0, max_abs_roll = 0.0;  ///< [rad]
  double max_speed = 0.0;                          ///< [m/s]
  /// Smallest clearance from impassable cells over the samples [m]; +infinity on a map
  /// without any.
  double min_clearance_m = 0.0;
  /// The independent re-check: for a candidate against the planning problem (its goal region),
  /// for a refinement the verdict's (the exact goal within the solver's tolerances).
  CheckReport check;
  std::string homotopy;  ///< signature over the refiner's reference frames
};

/// The outcome of one refinement.
struct RefinementResult {
  ocp::SolveStatus status = ocp::SolveStatus::kError;
  std::string reason;                         ///< why, for anything but kConverged
  RefineMethod method = RefineMethod::kAuto;  ///< the method used (never kAuto once solved)
  std::string method_rule;                    ///< why kAuto chose it
  models::Trajectory candidate;               ///< the candidate with every column (derived)
  std::vector<std::string> derived_columns;   ///< columns the candidate lacked
  std::optional<TrajectoryFigures> candidate_figures;  ///< absent when it could not be measured
  std::optional<TrajectoryFigures> refined_figures;    ///< absent when nothing re-simulated
  bool homotopy_kept = false;
  int intervals = 0;               ///< direct transcription's final interval count
  int coarse_intervals = 0;        ///< the coarse solve's intervals (0: none)
  double corridor_radius_m = 0.0;  ///< the corridor of the class retry (0: none needed)
  double guess_shortcut_m = 0.0;   ///< how much shorter the shortcut guess was [m] (0: not used)
  ocp::SolveStatus coarse_status = ocp::SolveStatus::kError;  ///< the coarse solve's outcome
  int margin_rounds = 0;           ///< fine direct transcription solves (1 + margin retries used)
  double speed_margin_used = 0.0;  ///< the margins of the last solve (fractions)
  double limit_margin_used = 0.0;
  double clearance_used_m = 0.0;              ///< the clearance constraint (transcription)
  int iterations = 0;                         ///< solver iterations (all mesh rounds)
  double solve_time_ms = 0.0;                 ///< whole refinement [ms]
  std::vector<ocp::IterationRecord> history;  ///< per iteration: terminal error, cost
  ocp::VerifiedTrajectory verified;           ///< the independent re-simulation
  models::TrajectoryVerdict verdict;          ///< the verdict on verified.trajectory
  /// The refinement ended worse than its feasible candidate: the result is the candidate
  /// (status kDiverged, reason saying so), `verified` still the refinement's re-simulation.
  bool returned_candidate = false;
  std::optional<ocp::TranscriptionSolution> transcription;  ///< shooting / collocation
  std::optional<ocp::BoundaryValueSolution> parametric;     ///< newton, ipopt
  /// refined cost / candidate cost (NaN unless both are known).
  double costRatio() const;
};

/// Refines candidates of one problem. Holds the clearance map (built once); immutable after
/// construction, but Ipopt 3.11 is not thread-safe: one refine() at a time per process.
///
/// The status of a refinement is the verdict (models::judgeTrajectory) on its re-simulated
/// trajectory against the boundary-value problem (the exact goal within
/// `options.parametric.criteria`), plus two rules of its own: the class must be kept
/// (else kInfeasible), and a refinement worse than its feasible candidate is not converged
/// (kDiverged, returned_candidate).
class CandidateRefiner {
 public:
  /// The wall clock left to one refine() (internal; no limit: +infinity).
  struct Deadline {
    std::chrono::steady_clock::time_point started;
    std::optional<double> limit_s;
    const std::atomic<bool>* stop = nullptr;
    /// Seconds left (+infinity without a limit), never below 0.
    double secondsLeft() const;
    /// Whether the limit has passed or a stop was requested.
    bool over() const;
  };

  /// `problem` (map, vehicle, limits, tables, start, goal region), `bvp` (its boundary-value
  /// form: exact start and goal, cost, tables) and `frames` must outlive the refiner.
  CandidateRefiner(const PlanningProblem& problem, const ocp::BoundaryValueProblem& bvp,
                   const ReferenceFrames& frames, const RefinementOptions& options = {});

  /// Refines one candidate. Never throws (except std::bad_alloc): a candidate that cannot be
  /// used (a single point, NaN, off the map) gives kError with the sample at fault; a solver
  /// failure gives its status; a converged solve that breaks a limit or leaves the class gives
  /// kInfeasible, one that misses the goal kDiverged.
  RefinementResult refine(const models::Trajectory& candidate) const;

  /// The figures of a trajectory with every column (cost, extremes, check, class).
  TrajectoryFigures measure(const models::Trajectory& trajectory,
                            const models::TrajectoryRequirements& requirements) const;
  /// What a candidate is held to: the planning problem (its goal region).
  const models::TrajectoryRequirements& candidateRequirements() const {
    return candidate_requirements_;
  }
  /// What a refinement is held to: the boundary-value problem's exact goal within the
  /// solver's tolerances.
  const models::TrajectoryRequirements& refinedRequirements() const {
    return refined_requirements_;
  }

  const RefinementOptions& options() const { return options_; }
  const ReferenceFrames& frames() const { return *frames_; }

 private:
  // Direct transcription from `guess` with the margin retries, keeping clear of the impassable
  // cells of `clearance`; fills `out` (status, reason, verified, history, intervals, clearance).
  void transcribe(const ocp::TranscriptionGuess& guess, const TrajectoryFigures& before,
                  const terrain::ClearanceMap& clearance, const Deadline& deadline,
                  RefinementResult& out) const;
  // The candidate's cost plus its last point's distance to the exact goal at v_max: what a
  // refinement must not exceed.
  double candidateCostAtGoal(const TrajectoryFigures& before, const RefinementResult& out) const;
  bool worseThanCandidate(const TrajectoryFigures& before, const RefinementResult& out) const;
  // Applies the worse-than-candidate rule and the total time.
  RefinementResult& finishRefinement(const TrajectoryFigures& before, RefinementResult& out,
                                     std::chrono::steady_clock::time_point started) const;
  // The figures without the check.
  TrajectoryFigures figuresOf(const models::Trajectory& trajectory) const;
  // Fills refined_figures, verdict, homotopy_kept and the final status from out.verified, the
  // solve's `status` / `reason` (already the verdict's) and its `verdict` (which must be
  // against refinedRequirements()); a converged solve that left the class is kInfeasible.
  void accept(ocp::SolveStatus status, std::string reason, models::TrajectoryVerdict verdict,
              const TrajectoryFigures& before, RefinementResult& out) const;
  // The candidate's path with greedy straight shortcuts keeping `clearance` [m].
  std::vector<Eigen::Vector2d> shortcutPath(const std::vector<Eigen::Vector2d>& path,
                                            double clearance) const;
  // The map with every cell farther than corridor_radius_m from the candidate made lethal.
  terrain::ElevationMap corridorMap(const models::Trajectory& candidate) const;

  const PlanningProblem* problem_;
  const ocp::BoundaryValueProblem* bvp_;
  const ReferenceFrames* frames_;
  RefinementOptions options_;
  terrain::ClearanceMap clearance_;
  models::TrajectoryRequirements candidate_requirements_;
  models::TrajectoryRequirements refined_requirements_;
};

/// kAuto's rule for one candidate of planar length `length_m`, smallest clearance
/// `min_clearance_m` and `curvature_sign_changes`: ipopt (polynomial controls) when all three
/// are within the options' parametric_* bounds, else collocation; a configured method is returned
/// as it is. Writes the reason into `rule`. A failed ipopt falls back to collocation.
RefineMethod chooseRefineMethod(const RefinementOptions& options, double length_m,
                                double min_clearance_m, int curvature_sign_changes,
                                std::string& rule);

}  // namespace terratraj::search
