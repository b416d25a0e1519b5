#pragma once
// solveSeeded(): the optimal-control core's front door (`terratraj solve`, the `auto` method):
// global seeds, then a local solver from each, and the best verified result.
//
// Seeds (solveSeeded's `initial_guess: auto`): the Dubins words between start and goal with the
// vehicle's turning radius (ocp::dubinsPaths), shortest first, each time-parametrised under
// v_max, a_max and omega_max (ocp::guessFromPath); when no word gives a verified trajectory (or
// none can be tried: every word crosses an impassable cell), a search seed: the kinodynamic
// PRM's first solution, refined in its homotopy class (refine::CandidateRefiner). A word that
// crosses slopes beyond the pitch or roll limits (`seed_limit_slack`) is tried after the search
// seed, not before it. `initial_guess: flat` keeps 004's flat-ground heuristic alone (the
// paper's behaviour).
//
// Solvers: shooting / collocation start from a seed's trajectory; the parametric methods
// (newton, newton_fd, ipopt, ceres) from the polynomial controls fitted to it, through the
// flat-ground optimum. `auto` uses collocation; when collocation fails from a word, the
// parametric ipopt from the same word and collocation again from ipopt's trajectory (ipopt's
// verified result counts too, unless a clearance is asked for: only the transcriptions hold
// it). Every attempt is verified (the verdict, the Segway's look-ups included);
// the best converged cost wins; a second word is tried when the first fails or is within
// `retry_length_ratio` of it, or when the best cost so far is above `retry_cost_ratio` x the
// word's bang-bang time; the search seed too, when it is above that ratio x the shortest
// word's. Each seed runs within a budget (`first_seed_time_s` for the
// first, `seed_time_s` for the others); the seeds cut by theirs (a step stopped by the clock)
// are retried, in the same order, with twice the budget, round after round, repeating only the
// steps the clock stopped (a portfolio: a seed on which the solver wanders costs its budget,
// not the whole time limit). Before
// any of this, a goal that cannot be reached at all (boxed in by slopes beyond the pitch and roll
// limits, lethal or no-data cells) is `infeasible` with the reason (models::checkGoalReachability).

#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/goal_reachability.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/ocp/transcription_solver.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::refine {

/// The solvers of the core.
enum class CoreMethod { kAuto, kNewton, kNewtonFd, kIpopt, kCeres, kShooting, kCollocation };
/// "auto", "newton", ...
const char* coreMethodName(CoreMethod method);

/// Where the solvers start.
enum class InitialGuessKind {
  kAuto,  ///< global seeds (Dubins words, a search where obstacles need one)
  kFlat,  ///< 004's flat-ground heuristic alone (the paper's behaviour; parametric methods)
};

/// The core's transcription defaults: intervals from the seed (transcription.intervals 0),
/// piecewise-linear controls (limits hold between nodes), 500 Ipopt iterations a round.
ocp::TranscriptionSolveOptions defaultCoreTranscription();

/// The search seed's PRM budget when SeededSolveOptions::search_time_s is absent [s]. The PRM
/// stops at its first solution (found in under 1 s on open maps, up to several seconds on rough
/// real DEMs), so the budget runs out only when the search finds nothing.
inline constexpr double kDefaultSearchTimeS = 10.0;
/// SeededSolveOptions::search_improve_milestones's default: 0.03 s of the PRM on the gully DEM,
/// 0.6 s on davosdorf (the PRM's route of a davosdorf Segway problem improved about 4,000 and
/// 8,700 milestones after its first solution).
inline constexpr std::size_t kDefaultSearchImproveMilestones = 8000;
/// SeededSolveOptions::search_improvements's default.
inline constexpr int kDefaultSearchImprovements = 2;

/// One attempt: a seed and a solver.
struct SeedAttempt {
  std::string seed;    ///< "dubins LSL (12.3 m)", "flat heuristic", "search (prm)"
  std::string method;  ///< the solver
  ocp::SolveStatus status = ocp::SolveStatus::kError;
  std::string reason;
  double cost = 0.0;  ///< verified cost (NaN without a re-simulation)
  double time_ms = 0.0;
  double budget_s = 0.0;  ///< the wall clock its seed's chain was allotted [s] (inf: none)
  /// The wall clock its seed's chain was given: budget_s capped by the solve's time left when
  /// the chain started [s] (inf: none). A chain the clock cut is tried again only with more.
  double time_given_s = 0.0;
  int round = 0;  ///< 0: the seed's first budget; r: retried with 2^r times it
  /// Stopped by the clock (SeededSolution::time_limit_reached): a later round may repeat it.
  bool time_limit_reached = false;
};

/// The default of SeededSolveOptions::seed_time_s [s].
inline constexpr double kDefaultSeedTimeS = 10.0;
/// The default of SeededSolveOptions::first_seed_time_s [s].
inline constexpr double kDefaultFirstSeedTimeS = 30.0;

/// Settings of solveSeeded().
struct SeededSolveOptions {
  CoreMethod method = CoreMethod::kAuto;
  InitialGuessKind initial_guess = InitialGuessKind::kAuto;
  /// The parametric methods' settings (criteria, iterations; method set per attempt). Its
  /// criteria are the verdict's terminal tolerances for every method.
  ocp::BoundaryValueOptions parametric;
  /// Shooting / collocation settings (scheme, margins, rounds, max_intervals, clearance);
  /// transcription.intervals <= 0: one interval per `interval_length_m` of the seed, within
  /// [min_intervals, max_intervals / 2].
  ocp::TranscriptionSolveOptions transcription = defaultCoreTranscription();
  double interval_length_m = 0.25;    ///< > 0
  double turning_per_interval = 0.1;  ///< ... plus one interval per this much turning [rad], > 0
  int min_intervals = 20;             ///< >= 2
  int max_words = 3;                  ///< Dubins words tried at most, >= 1
  /// A further word is tried when the previous attempt failed, or when its Dubins length is at
  /// most this ratio times the shortest's (its optimum on the terrain may be better), >= 1.
  double retry_length_ratio = 1.2;
  /// After a convergence, in the first round, a further word is also tried (even one beyond
  /// the attitude limits) when the best verified cost is above this ratio x the word's
  /// bang-bang time along its length (v_max, a_max, the end speeds): the search seed's
  /// refinement keeps the PRM's class, which can be a detour far slower than a word (davosdorf
  /// Segway, 47.1 s against a word's 16.3 s), >= 1. For the transcription methods the search
  /// seed (not tried yet) is tried too when the best cost is above this ratio x the shortest
  /// word's bang-bang time: a word's optimum can go far round a slope the PRM's route passes
  /// (davosdorf Segway, 18.0 s against 9.9 s).
  double retry_cost_ratio = 1.5;
  /// ipopt (which holds v_max and a_max): the speed polynomial's order at least this, so the
  /// speed is free to rise to v_max and return to the end speeds (rest to rest works), >= 1.
  /// newton and ceres hold no limit and keep the problem's order (a free speed would be
  /// unbounded for them).
  int ipopt_speed_order = 3;
  /// ipopt's iterations, >= 1; absent: 3 x parametric.max_iterations (limited-memory
  /// quasi-Newton iterations: more, and cheaper, than newton's).
  std::optional<int> ipopt_max_iterations;
  double seed_spacing_m = 0.1;  ///< samples of a seed path [m], > 0
  /// A word along which the vehicle (at the word's heading) leaves pitch_max or roll_max by
  /// more than this (relative, >= 0) is tried after the search seed, not before it.
  double seed_limit_slack = 0.1;
  /// Search seed: the PRM's budget [s] when no word gave a converged result (0: none); it
  /// stops at its first solution, so the budget is spent only when it finds none. Absent:
  /// kDefaultSearchTimeS. Never more than half the time left to the search seed's chain (its
  /// budget, seed_time_s, or the solve's time left; searchSeedBudget()).
  /// `terratraj solve` passes planner.time_limit_s.
  std::optional<double> search_time_s;
  std::uint64_t search_seed = 1;  ///< the PRM's random seed
  /// Search seed: when the refinement of the PRM's route ends without a verified trajectory on
  /// its own (not stopped by the clock), the PRM continues for this many more milestones (a
  /// count, so the route is the same every run; within the chain's time) and its better route,
  /// if it found one, is refined. 0: the first solution alone. A first solution can wind where
  /// a later route does not: a Segway problem on davosdorf whose first route's refinement ends
  /// infeasible after 7 s converges in 1.5 s from the route 8,000 milestones later (0.6 s of
  /// the PRM there; 0.03 s on the gully DEM).
  std::size_t search_improve_milestones = kDefaultSearchImproveMilestones;
  /// At most this many continuations after a failed refinement, >= 0. Both for the
  /// transcription methods (auto, collocation, shooting); newton and ceres refine the first
  /// route alone.
  int search_improvements = kDefaultSearchImprovements;
  /// With initial_guess kAuto and a map, first checked: whether the goal can be reached at all
  /// (models::checkGoalReachability); when not, kInfeasible with its reason before any seed is
  /// tried. std::nullopt: not checked.
  std::optional<models::GoalReachabilityOptions> reachability = models::GoalReachabilityOptions{};
  /// Each seed's first budget [s], > 0: the wall clock of its chain of attempts (a word's
  /// solve and, for auto, its bridge through ipopt; the search seed's PRM and refinement).
  /// A seed cut by its budget is tried again after the others have had theirs, with twice the
  /// budget, round after round, until one converges or time_limit_s runs out, so one seed on
  /// which the solver wanders cannot spend the time another needs (solveSeeded). <= 0 or
  /// infinite: no budgets (each seed may use all the time left).
  double seed_time_s = kDefaultSeedTimeS;
  /// The first seed's first budget [s] (at least seed_time_s): the first seed in the order, the
  /// shortest word within the attitude limits (else the search seed), is the likeliest to
  /// converge, and on rough terrain its mesh rounds can take tens of seconds (a Segway problem
  /// on davosdorf converges from its first word in 32 s).
  double first_seed_time_s = kDefaultFirstSeedTimeS;
  std::optional<double> time_limit_s;  ///< wall clock of the whole solve [s]; absent: none
  /// Set from outside (SIGINT): no further attempt, and the solver running ends at its next
  /// iteration (as at its time limit).
  const std::atomic<bool>* stop = nullptr;
  /// Called after each attempt with its record (progress; may be empty). Must not throw.
  std::function<void(const SeedAttempt&)> on_attempt;
};

/// The iterations of the parametric ipopt under `options`.
int ipoptMaxIterations(const SeededSolveOptions& options);

/// The first seed's first budget under `options` [s]: first_seed_time_s, never below
/// seed_time_s.
double firstSeedBudget(const SeededSolveOptions& options);

/// The outcome.
struct SeededSolution {
  ocp::SolveStatus status = ocp::SolveStatus::kError;  ///< the verdict's, of the best attempt
  std::string reason;
  std::string method;                                       ///< the solver that produced the result
  std::string initial_guess;                                ///< its seed
  ocp::VerifiedTrajectory verified;                         ///< the re-simulation of the result
  models::TrajectoryVerdict verdict;                        ///< the check of verified.trajectory
  std::optional<ocp::BoundaryValueSolution> parametric;     ///< the result's, parametric
  std::optional<ocp::VerifiedTranscription> transcription;  ///< the result's, transcription
  std::vector<ocp::IterationRecord> history;                ///< the result's iterations
  int iterations = 0;                                       ///< of every attempt
  std::vector<SeedAttempt> attempts;                        ///< every attempt, in order
  std::optional<models::GoalReachability> reachability;     ///< the check, when made
  /// The result's attempt ended by its clock (a solver's time limit, a verification round
  /// it could not start, the search seed's PRM budget cut below search_time_s): with more time
  /// it may end otherwise. Else the same seed and options give the same result again, which
  /// solveSeeded's later rounds do not repeat. Also set, with the reason saying so, when
  /// time_limit_s (or a stop) ended the rounds before every cut seed had its next budget.
  bool time_limit_reached = false;
  double total_time_ms = 0.0;
};

/// The solution of one verified transcription (its status, reason, re-simulation, verdict,
/// history and iterations; the transcription kept), produced by `method` from `initial_guess`
/// (names as the report prints them).
SeededSolution seededSolutionOf(ocp::VerifiedTranscription result, std::string method,
                                std::string initial_guess);

/// Solves `problem` on `vehicle` (map: the verdict's map rules and the obstacles of the seeds;
/// may be null). Never throws (except std::bad_alloc). Ipopt 3.11 is not thread-safe: one solve
/// at a time per process.
SeededSolution solveSeeded(const models::TerrainFollowingModel& vehicle,
                           const ocp::BoundaryValueProblem& problem,
                           const terrain::ElevationMap* map, const SeededSolveOptions& options);

}  // namespace terratraj::refine
