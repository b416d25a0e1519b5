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
#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/refine/refinement_options.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/clearance_map.hpp"

namespace terratraj::refine {

/// The figures of one trajectory (a candidate or its refinement).
struct TrajectoryFigures {
  double cost = 0.0;        ///< the problem's cost functional, integrated over the samples [s]
  double duration_s = 0.0;  ///< [s]
  double length_m = 0.0;    ///< planar length [m]
  double max_abs_pitch = 0.0, max_abs_roll = 0.0;  ///< [rad]
  double max_speed = 0.0;                          ///< [m/s]
  /// Smallest clearance over the samples [m]: from impassable cells, and from where the
  /// surface is undefined beside no data less the vehicle's sampling radius
  /// (terrain::ClearanceMap); +infinity on a map without any impassable cell.
  double min_clearance_m = 0.0;
  /// The independent re-check: for a candidate against the planning problem (its goal region),
  /// for a refinement the verdict's (the exact goal within the solver's tolerances).
  models::CheckReport check;
  /// Signature over the refiner's reference frames of the path closed at the problem's exact
  /// start and goal (ReferenceFrames::signatureBetween).
  std::string homotopy;
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
  int coarse_iterations = 0;       ///< its Ipopt iterations (part of `iterations`)
  double corridor_radius_m = 0.0;  ///< the corridor of the class retry (0: none needed)
  double guess_shortcut_m = 0.0;   ///< how much shorter the shortcut guess was [m] (0: not used)
  /// How much faster the candidate's path re-timed by the speed pass was than the candidate, for
  /// a slow candidate whose shortcut is not used [s] (0: not used).
  double guess_retimed_s = 0.0;
  ocp::SolveStatus coarse_status = ocp::SolveStatus::kError;  ///< the coarse solve's outcome
  /// How far the coarse solution breaks the ground's limits read at the fine mesh's points
  /// (ocp::guessLimitExcess, relative); the fine solve starts from it only when that is at
  /// most mesh_excess or the guess's own.
  double coarse_limit_excess = 0.0;
  bool coarse_used = false;  ///< the fine solve started from the coarse solution
  /// The fine solve started Ipopt's barrier warm (RefinementOptions::warm_start_time_ratio).
  bool warm_start = false;
  int margin_rounds = 0;           ///< fine direct transcription solves (1 + margin retries used)
  double speed_margin_used = 0.0;  ///< the margins of the last solve (fractions)
  double limit_margin_used = 0.0;
  double clearance_used_m = 0.0;  ///< the clearance constraint (transcription)
  int iterations = 0;             ///< solver iterations (all mesh rounds)
  double solve_time_ms = 0.0;     ///< whole refinement [ms]
  /// The clock (RefinementOptions::time_limit_s) or a stop ended a solve (the parametric one,
  /// the coarse mesh, a round of the fine one) or kept a step from running (kAuto's collocation
  /// after a parametric solve that failed, the class retry in a corridor): with more time the
  /// result may differ. False: the same options give the same result.
  bool time_limit_reached = false;
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
  /// The wall clock left to one refine() (internal).
  using Deadline = ocp::Deadline;

  /// `problem` (map, vehicle, limits, tables, start, goal region), `bvp` (its boundary-value
  /// form: exact start and goal, cost, tables) and `frames` must outlive the refiner.
  CandidateRefiner(const search::PlanningProblem& problem, const ocp::BoundaryValueProblem& bvp,
                   const search::ReferenceFrames& frames, const RefinementOptions& options = {});

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
  const search::ReferenceFrames& frames() const { return *frames_; }

 private:
  // The start already meets the goal: the one-row trajectory at the start, judged into `out`;
  // returns the status.
  ocp::SolveStatus refineAtStart(RefinementResult& out) const;
  // Polynomial controls (out.method: newton or ipopt; the speed free) from the flat-ground
  // optimum, accepted into `out`.
  void solveParametric(const TrajectoryFigures& before, const Deadline& deadline,
                       RefinementResult& out) const;
  // Direct transcription from `guess` with the margin retries, keeping clear of the impassable
  // cells of `clearance`; fills `out` (status, reason, verified, history, intervals, clearance).
  void transcribe(const ocp::TranscriptionGuess& guess, const TrajectoryFigures& before,
                  const terrain::ClearanceMap& clearance, const Deadline& deadline,
                  RefinementResult& out) const;
  // The coarse mesh's solve from `guess` (coarse_intervals, the fine options otherwise, the
  // speed margin applied): its solution when it converged and breaks the ground's limits at the
  // fine mesh's points by at most `mesh_excess` or the guess's own excess, else std::nullopt;
  // fills out's coarse figures, history and iterations.
  std::optional<ocp::TranscriptionGuess> solveCoarse(const ocp::TranscriptionGuess& guess,
                                                     const ocp::DirectTranscriptionOptions& fine,
                                                     double mesh_excess, int coarse_intervals,
                                                     const Deadline& deadline,
                                                     RefinementResult& out) const;
  // The candidate's cost plus its last point's distance to the exact goal at v_max: what a
  // refinement must not exceed.
  double candidateCostAtGoal(const TrajectoryFigures& before, const RefinementResult& out) const;
  bool worseThanCandidate(const TrajectoryFigures& before, const RefinementResult& out) const;
  // Applies the worse-than-candidate rule and the total time.
  RefinementResult& finishRefinement(const TrajectoryFigures& before, RefinementResult& out,
                                     std::chrono::steady_clock::time_point started) const;
  // The guess the optimiser starts from: the candidate's (`candidate`), its shortcut path's
  // (a wiggly candidate) or its path re-timed by the speed pass (a slow one); sets
  // out.guess_shortcut_m / out.guess_retimed_s when used.
  ocp::TranscriptionGuess startingGuess(const TrajectoryFigures& before,
                                        const ocp::TranscriptionGuess& candidate,
                                        RefinementResult& out) const;
  // The duration under which a guess along a path of `length` [m] counts as near optimal:
  // warm_start_time_ratio x the bang-bang time along it [s].
  double nearOptimalTime(double length) const;
  // The homotopy signature (as text) of a path closed at the problem's exact start and goal.
  std::string classOf(const std::vector<Eigen::Vector2d>& path) const;
  // The figures without the check.
  TrajectoryFigures figuresOf(const models::Trajectory& trajectory) const;
  // Fills refined_figures, verdict, homotopy_kept and the final status from out.verified, the
  // solve's `status` / `reason` (already the verdict's) and its `verdict` (which must be
  // against refinedRequirements()); a converged solve that left the class is kInfeasible.
  void accept(ocp::SolveStatus status, std::string reason, models::TrajectoryVerdict verdict,
              const TrajectoryFigures& before, RefinementResult& out) const;
  // The candidate's path with greedy straight shortcuts keeping `clearance` [m] from impassable
  // cells, along which the vehicle can be placed.
  std::vector<Eigen::Vector2d> shortcutPath(const std::vector<Eigen::Vector2d>& path,
                                            double clearance) const;
  // The map with every cell farther than corridor_radius_m from the candidate made lethal.
  terrain::ElevationMap corridorMap(const models::Trajectory& candidate) const;

  const search::PlanningProblem* problem_;
  const ocp::BoundaryValueProblem* bvp_;
  const search::ReferenceFrames* frames_;
  RefinementOptions options_;
  terrain::ClearanceMap clearance_;
  models::TrajectoryRequirements candidate_requirements_;
  models::TrajectoryRequirements refined_requirements_;
};

}  // namespace terratraj::refine
