#include "terratraj/refine/seeded_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "attempt_log.hpp"
#include "end_state_check.hpp"
#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/dubins_path.hpp"
#include "terratraj/ocp/initial_guess.hpp"
#include "terratraj/ocp/start_at_goal.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/refine/search_seed.hpp"
#include "terratraj/search/bang_bang_bound.hpp"

namespace terratraj::refine {
namespace {

using detail::AttemptLog;

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string formatLength(double metres) {
  std::ostringstream text;
  text.precision(3);
  text << metres;
  return text.str();
}

// A Dubins word as a seed: its path sampled, time-parametrised under the limits.
struct Seed {
  std::string name;
  double length = 0.0;  ///< [m]
  ocp::TranscriptionGuess guess;
  double turning = 0.0;  ///< total |heading change| along the path [rad]
  /// Whether the vehicle, placed along the path at its heading, leaves pitch_max or roll_max
  /// (with the options' slack) somewhere: the word crosses a slope it would have to go round.
  bool beyond_limits = false;
};

// What a sampled path meets on the map, in one placement of the vehicle per point.
enum class WordTerrain {
  kClear,
  kBeyondLimits,  ///< the vehicle, at the path's heading, leaves pitch or roll limits (+ slack)
  kImpassable,    ///< a lethal, no-data or off-map cell, or where the vehicle cannot be placed
};

// The path's terrain: impassable where it crosses a lethal, no-data or off-map cell or passes
// where the vehicle cannot be placed (a contact point, or the terrain surface's stencil, over
// no data or off the map: a word beside a no-data region); else beyond the limits where the
// vehicle leaves pitch_max or roll_max by more than `slack` (relative). `workspace` is the
// caller's.
WordTerrain classifyWord(const std::vector<ocp::PathPoint2>& points,
                         const terrain::ElevationMap& map,
                         const models::TerrainFollowingModel& vehicle,
                         const models::VehicleLimits& limits, double slack,
                         models::AttitudeWorkspace& workspace) {
  models::AttitudeResult placed;
  bool beyond = false;
  for (const ocp::PathPoint2& p : points) {
    const std::optional<terrain::CellIndex> cell = map.geometry().cellAt({p.x, p.y});
    if (!cell || map.isNoData(*cell) || map.isLethal(*cell)) return WordTerrain::kImpassable;
    if (vehicle.compute({p.x, p.y, p.heading}, workspace, placed) != models::AttitudeStatus::kOk) {
      return WordTerrain::kImpassable;
    }
    beyond = beyond || std::abs(placed.attitude.pitch) > (1.0 + slack) * limits.pitch_max ||
             std::abs(placed.attitude.roll) > (1.0 + slack) * limits.roll_max;
  }
  return beyond ? WordTerrain::kBeyondLimits : WordTerrain::kClear;
}

// The turning radius of the seeds: kappa_max, and omega_max at the faster end speed.
double seedRadius(const ocp::BoundaryValueProblem& problem) {
  const models::VehicleLimits& l = problem.limits;
  const double v_turn = std::max(problem.start.v, problem.goal.v);
  const double kappa = v_turn > 0.0 ? std::min(l.kappa_max, l.omega_max / v_turn) : l.kappa_max;
  return 1.0 / kappa;
}

// The Dubins seeds, shortest first; `blocked` counts the words dropped for crossing an
// impassable cell of `map` or passing where `vehicle` cannot be placed.
std::vector<Seed> dubinsSeeds(const models::TerrainFollowingModel& vehicle,
                              const ocp::BoundaryValueProblem& problem,
                              const terrain::ElevationMap* map, const SeededSolveOptions& options,
                              int& blocked) {
  std::vector<Seed> seeds;
  blocked = 0;
  models::AttitudeWorkspace workspace;
  const std::vector<ocp::DubinsPath> paths =
      ocp::dubinsPaths({problem.start.x, problem.start.y, problem.start.heading},
                       {problem.goal.x, problem.goal.y, problem.goal.heading}, seedRadius(problem));
  for (const ocp::DubinsPath& path : paths) {
    if (static_cast<int>(seeds.size()) >= options.max_words) break;
    const std::vector<ocp::PathPoint2> points = path.sample(options.seed_spacing_m);
    const WordTerrain terrain = map != nullptr ? classifyWord(points, *map, vehicle, problem.limits,
                                                              options.seed_limit_slack, workspace)
                                               : WordTerrain::kClear;
    if (terrain == WordTerrain::kImpassable) {
      ++blocked;
      continue;
    }
    std::vector<Eigen::Vector2d> xy;
    xy.reserve(points.size());
    for (const ocp::PathPoint2& p : points) xy.emplace_back(p.x, p.y);
    Expected<ocp::TranscriptionGuess> guess =
        ocp::guessFromPath(xy, problem, options.seed_spacing_m);
    if (!guess) continue;
    const double turning =
        (path.word == ocp::DubinsWord::kLSL || path.word == ocp::DubinsWord::kRSR ||
         path.word == ocp::DubinsWord::kLSR || path.word == ocp::DubinsWord::kRSL)
            ? (path.lengths[0] + path.lengths[2]) / path.radius
            : path.length() / path.radius;
    seeds.push_back({std::string("dubins ") + ocp::dubinsWordName(path.word) + " (" +
                         formatLength(path.length()) + " m)",
                     path.length(), std::move(*guess), turning,
                     terrain == WordTerrain::kBeyondLimits});
  }
  return seeds;
}

ocp::BoundaryValueMethod parametricMethod(CoreMethod method) {
  switch (method) {
    case CoreMethod::kNewtonFd:
      return ocp::BoundaryValueMethod::kNewtonFd;
    case CoreMethod::kIpopt:
      return ocp::BoundaryValueMethod::kIpopt;
    case CoreMethod::kCeres:
      return ocp::BoundaryValueMethod::kCeres;
    default:
      return ocp::BoundaryValueMethod::kNewton;
  }
}

bool isTranscription(CoreMethod method) {
  return method == CoreMethod::kAuto || method == CoreMethod::kShooting ||
         method == CoreMethod::kCollocation;
}

}  // namespace

ocp::TranscriptionSolveOptions defaultCoreTranscription() {
  ocp::TranscriptionSolveOptions options;
  options.transcription.intervals = 0;
  options.transcription.linear_controls = true;
  options.transcription.max_iterations = 500;
  return options;
}

int ipoptMaxIterations(const SeededSolveOptions& options) {
  return options.ipopt_max_iterations.value_or(3 * options.parametric.max_iterations);
}

const char* coreMethodName(CoreMethod method) {
  switch (method) {
    case CoreMethod::kAuto:
      return "auto";
    case CoreMethod::kNewton:
      return "newton";
    case CoreMethod::kNewtonFd:
      return "newton_fd";
    case CoreMethod::kIpopt:
      return "ipopt";
    case CoreMethod::kCeres:
      return "ceres";
    case CoreMethod::kShooting:
      return "shooting";
    case CoreMethod::kCollocation:
      return "collocation";
  }
  return "?";
}

namespace {

// The transcription guess of a verified trajectory; nothing when it has none (a trajectory
// with fewer than two samples).
std::optional<ocp::TranscriptionGuess> guessOrNothing(const models::Trajectory& trajectory) {
  Expected<ocp::TranscriptionGuess> guess = ocp::guessFromTrajectory(trajectory);
  if (!guess) return std::nullopt;
  return std::move(*guess);
}

// One attempt from one seed (null: the flat heuristic) with one solver.
SeededSolution attempt(const models::TerrainFollowingModel& vehicle,
                       const ocp::BoundaryValueProblem& problem, const terrain::ElevationMap* map,
                       const SeededSolveOptions& options, const Seed* seed,
                       std::optional<double> time_left_s) {
  SeededSolution out;
  out.initial_guess = seed != nullptr ? seed->name : "flat heuristic (004)";
  if (isTranscription(options.method)) {
    ocp::TranscriptionSolveOptions solve = options.transcription;
    solve.criteria = options.parametric.criteria;
    solve.map = map;
    solve.stop = options.stop;
    solve.time_limit_s = time_left_s;
    if (options.method == CoreMethod::kShooting) {
      solve.transcription.scheme = ocp::TranscriptionScheme::kMultipleShooting;
    } else if (solve.transcription.scheme == ocp::TranscriptionScheme::kMultipleShooting) {
      solve.transcription.scheme = ocp::TranscriptionScheme::kHermiteSimpson;
    }
    if (solve.transcription.intervals <= 0) {
      // One interval per interval_length_m of path and per turning_per_interval of heading.
      const double length = seed != nullptr ? seed->length : 1.0;
      const double turning = seed != nullptr ? seed->turning : 0.0;
      const int wanted = static_cast<int>(
          std::ceil(length / options.interval_length_m + turning / options.turning_per_interval));
      solve.transcription.intervals = std::clamp(
          wanted, options.min_intervals, std::max(options.min_intervals, solve.max_intervals / 2));
    }
    solve.max_intervals = std::max(solve.max_intervals, solve.transcription.intervals);
    return seededSolutionOf(ocp::solveTranscription(vehicle, problem, seed->guess, solve),
                            options.method == CoreMethod::kShooting ? "shooting" : "collocation",
                            std::move(out.initial_guess));
  }
  ocp::BoundaryValueProblem posed = problem;
  if (options.method == CoreMethod::kIpopt) {
    posed.orders.speed = std::max(posed.orders.speed, options.ipopt_speed_order);
  }
  ocp::BoundaryValueOptions settings = options.parametric;
  settings.method = parametricMethod(options.method);
  if (options.method == CoreMethod::kIpopt) settings.max_iterations = ipoptMaxIterations(options);
  if (time_left_s) settings.time_limit_s = *time_left_s;
  settings.stop = options.stop;
  if (seed != nullptr) {
    std::vector<double> t, v, omega;
    for (std::size_t i = 0; i < seed->guess.t.size(); ++i) {
      t.push_back(seed->guess.t[i]);
      v.push_back(seed->guess.points[i](3));
      omega.push_back(seed->guess.points[i](4));
    }
    settings.initial_q = ocp::fitParametricControls(posed, t, v, omega, seed->length);
  }
  out.method = coreMethodName(options.method);
  ocp::BoundaryValueSolution result = ocp::solveBoundaryValue(vehicle, posed, settings, map);
  out.status = result.status;
  out.reason = result.reason;
  out.verified = result.verified;
  out.verdict = result.verdict;
  out.history = result.solver.history;
  out.iterations = result.solver.iterations;
  out.time_limit_reached = result.time_limit_reached;
  out.parametric = std::move(result);
  return out;
}

// solveSeeded's first step: whether the goal can be reached at all (with initial_guess kAuto, a
// map, and the check enabled; else std::nullopt), within what is left of the time limit.
std::optional<models::GoalReachability> checkReachability(
    const models::TerrainFollowingModel& vehicle, const ocp::BoundaryValueProblem& problem,
    const terrain::ElevationMap* map, const SeededSolveOptions& options,
    const ocp::Deadline& deadline) {
  if (options.initial_guess != InitialGuessKind::kAuto || map == nullptr || !options.reachability ||
      ocp::startMeetsGoal(problem, options.parametric.criteria)) {
    return std::nullopt;
  }
  models::GoalReachabilityOptions check = *options.reachability;
  if (const std::optional<double> left = deadline.left()) {
    check.time_limit_s = std::min(check.time_limit_s.value_or(*left), *left);
  }
  if (std::optional<models::GoalReachability> end = detail::checkEndStates(vehicle, problem)) {
    return end;
  }
  models::VehicleLimits limits = problem.limits;
  if (problem.tables.segway != nullptr) {
    // Where its look-ups allow no speed, the Segway cannot drive: a pitch limit.
    limits.pitch_max = std::min(limits.pitch_max, problem.tables.segway->bounds.drivableSlope());
  }
  return models::checkGoalReachability(
      vehicle, *map, limits, {problem.start.x, problem.start.y, problem.start.heading},
      {problem.goal.x, problem.goal.y, problem.goal.heading}, check);
}

// The flat heuristic (initial_guess flat, or a start already at the goal): for a
// transcription, from the parametric (newton) flat solution's trajectory, as 004 would have it.
SeededSolution attemptFlat(const models::TerrainFollowingModel& vehicle,
                           const ocp::BoundaryValueProblem& problem,
                           const terrain::ElevationMap* map, const SeededSolveOptions& options,
                           const ocp::Deadline& deadline) {
  if (!isTranscription(options.method)) {
    return attempt(vehicle, problem, map, options, nullptr, deadline.left());
  }
  ocp::BoundaryValueOptions flat = options.parametric;
  flat.method = ocp::BoundaryValueMethod::kNewton;
  const ocp::BoundaryValueSolution parametric =
      ocp::solveBoundaryValue(vehicle, problem, flat, map);
  std::optional<ocp::TranscriptionGuess> guess;
  if (parametric.verified.ok) guess = guessOrNothing(parametric.verified.trajectory);
  if (!guess) guess = ocp::TranscriptionGuess{};
  const Seed seed{"flat heuristic (004) via newton", parametric.verified.length, *guess, 0.0};
  return attempt(vehicle, problem, map, options, &seed, deadline.left());
}

// Which steps of a word's chain ended on their own (not by the clock): the solvers are
// deterministic, so a later round skips them rather than spend its budget on the same result
// (a collocation that stopped at its iteration cap within the budget, 5-8 s on davosdorf).
struct ChainProgress {
  bool solved = false;         ///< the method's attempt from the word
  bool ipopt_ended = false;    ///< auto's bridge: the parametric ipopt from the word
  std::optional<Seed> bridge;  ///< its verified trajectory as a seed, when it gave one
  bool bridged = false;        ///< the whole bridge (ipopt, then collocation from it)
};

// auto, when collocation fails from a word: the parametric ipopt (few unknowns, free speed, the
// limits held) from the same word, and collocation again from its trajectory, which follows the
// terrain within the limits; within `within`. ipopt's verified result is a candidate too (its
// verdict checks every limit, the Segway's look-ups included), unless a clearance is asked for,
// which only the transcriptions hold. Returns whether the bridge ended on its own (neither step
// stopped by the clock): run again, it would end the same. An ipopt step that ended on its own
// is not run again when a later round repeats the bridge (`done`): only the collocation the
// clock stopped is.
bool bridgeThroughIpopt(const models::TerrainFollowingModel& vehicle,
                        const ocp::BoundaryValueProblem& problem, const terrain::ElevationMap* map,
                        const SeededSolveOptions& options, const Seed& seed,
                        const ocp::Deadline& within, ChainProgress& done, AttemptLog& log) {
  if (!done.ipopt_ended) {
    const bool clearance = options.transcription.transcription.model.clearance.map != nullptr;
    SeededSolveOptions parametric = options;
    parametric.method = CoreMethod::kIpopt;
    const Clock::time_point t0 = Clock::now();
    SeededSolution step = attempt(vehicle, problem, map, parametric, &seed, within.left());
    const bool timed_out = step.time_limit_reached;
    if (step.verified.ok) {
      if (std::optional<ocp::TranscriptionGuess> guess = guessOrNothing(step.verified.trajectory)) {
        done.bridge =
            Seed{"ipopt from " + seed.name, step.verified.length, std::move(*guess), seed.turning};
      }
    }
    log.record(std::move(step), t0, !clearance);
    if (timed_out) return false;
    done.ipopt_ended = true;
  }
  if (!done.bridge) return true;
  if (within.over()) return false;
  const Clock::time_point t1 = Clock::now();
  SeededSolution polished = attempt(vehicle, problem, map, options, &*done.bridge, within.left());
  const bool ended = !polished.time_limit_reached;
  log.record(std::move(polished), t1);
  return ended;
}

// When the rounds ended short of a convergence because of the clock, says so beside the best
// attempt's own reason (which alone reads as if that attempt had the last word): the solve's
// clock (or a stop) with seeds still cut (`seeds_cut`), or seeds the clock cut that the time
// left could not give more time than they had (`starved`).
void explainAnEndShortOfConvergence(const ocp::Deadline& deadline, bool seeds_cut, bool starved,
                                    AttemptLog& log) {
  if (log.empty() || log.converged()) return;
  const bool clock_ended = seeds_cut && deadline.over();
  if (!clock_ended && !starved) return;
  SeededSolution& best = log.best();
  best.time_limit_reached = true;
  std::ostringstream why_ended;
  why_ended << best.reason << "; ";
  if (clock_ended && deadline.stop() != nullptr && deadline.stop()->load()) {
    why_ended << "stopped in round " << log.round;
  } else if (clock_ended) {
    why_ended << "the solve's time limit of " << deadline.limit().value_or(0.0)
              << " s ran out in round " << log.round;
  } else {
    why_ended << "the solve's time limit of " << deadline.limit().value_or(0.0)
              << " s left the seeds cut by their budgets no more time than they had before, in "
                 "round "
              << log.round - 1;
  }
  why_ended << " of the seeds' budgets";
  best.reason = why_ended.str();
}

// The global seeds as a portfolio. The order: the Dubins words within the attitude limits
// (shortest first), the search seed (when no word converged and the words are blocked, steep,
// or the method a transcription), the words across slopes beyond the limits (an optimiser
// started across a slope may wander far before it finds the way round, which the search's
// route already follows). Each seed's chain runs within its budget (first_seed_time_s for the
// first, seed_time_s for the others); the seeds
// the budget cut are tried again, in the same order, with twice the budget, until one
// converges or the solve's deadline passes; a word's steps that ended on their own are not
// repeated.
void solveFromSeeds(const models::TerrainFollowingModel& vehicle,
                    const ocp::BoundaryValueProblem& problem, const terrain::ElevationMap* map,
                    const SeededSolveOptions& options, const ocp::Deadline& deadline,
                    AttemptLog& log) {
  int blocked = 0;
  const std::vector<Seed> seeds = dubinsSeeds(vehicle, problem, map, options, blocked);
  const double shortest = seeds.empty() ? 0.0 : seeds.front().length;
  const long steep_words = std::count_if(seeds.begin(), seeds.end(),
                                         [](const Seed& seed) { return seed.beyond_limits; });
  const bool search =
      map != nullptr && options.search_time_s.value_or(kDefaultSearchTimeS) > 0.0 &&
      (seeds.empty() || blocked > 0 || steep_words > 0 || isTranscription(options.method));
  const std::string why = blocked > 0 && seeds.empty()
                              ? "every Dubins word crosses an impassable cell or no data"
                          : steep_words > 0 && steep_words == static_cast<long>(seeds.size())
                              ? "every Dubins word crosses slopes beyond the pitch or roll limits"
                              : "no Dubins word gave a verified trajectory";
  std::vector<const Seed*> order;  // nullptr: the search seed
  for (const Seed& seed : seeds) {
    if (!seed.beyond_limits) order.push_back(&seed);
  }
  if (search) order.push_back(nullptr);
  for (const Seed& seed : seeds) {
    if (seed.beyond_limits) order.push_back(&seed);
  }
  // Every seed until one converges; after that, in the first round only, a further word within
  // the attitude limits no longer than retry_length_ratio x the shortest (its optimum on the
  // terrain may be better), or any word when the best cost is above retry_cost_ratio x the
  // word's bang-bang time (a search seed's detour), or the search seed when the best cost is
  // above retry_cost_ratio x the shortest word's (a word's detour round a slope: a Segway
  // problem on davosdorf converged at 18.0 s from a word, the PRM's route refines to 9.9 s).
  const auto wordTime = [&](double length) {
    return search::bangBangTime(length, problem.start.v, problem.goal.v, problem.goal.v,
                                problem.limits.v_max, problem.limits.a_max);
  };
  const auto wanted = [&](const Seed* seed) {
    if (log.empty() || !log.converged()) return true;
    if (log.round != 0) return false;
    const double best = log.best().verified.cost;
    if (seed == nullptr) {
      // The transcriptions only: newton and ceres hold no limit and keep their speed order, so
      // their cost measures no detour, and their search seed (refined by collocation) is only
      // the fallback when no word converged.
      return isTranscription(options.method) && !seeds.empty() &&
             best > options.retry_cost_ratio * wordTime(shortest);
    }
    if (!seed->beyond_limits && seed->length <= options.retry_length_ratio * shortest) return true;
    return best > options.retry_cost_ratio * wordTime(seed->length);
  };
  const bool budgeted = options.seed_time_s > 0.0 && std::isfinite(options.seed_time_s);
  // The first seed in the order (the shortest word within the limits, else the search seed) is
  // the likeliest: it gets first_seed_time_s, the others seed_time_s; doubled each round.
  const Seed* const first = order.empty() ? nullptr : order.front();
  const double first_budget = firstSeedBudget(options);
  // Which steps of each word's chain ended on their own (ChainProgress).
  std::map<const Seed*, ChainProgress> progress;
  // The time a seed's chain was last given [s], kept only when a retry would run that chain
  // again as it ran: a word none of whose steps ended on its own in that try (its first step
  // had the whole time; a step that ended is not repeated, so the steps after it would get more
  // than they had), the search seed from round 1 on (round 0 refines the PRM's first route
  // first, a retry its improved route). Such a seed the clock cut is tried again only with more
  // time: near the solve's deadline its doubled budget is capped by the time left, and with less
  // its chain ends as it did or sooner (a slope-dwell problem on davosdorf ran its search seed 14
  // more times, each with half the time of the one before, until its 60 s were gone).
  std::map<const Seed*, double> granted;
  const auto moreTimeThanBefore = [&](const Seed* seed) {
    const auto it = granted.find(seed);
    const std::optional<double> left = deadline.left();
    return it == granted.end() || !left || *left > it->second;
  };
  bool starved = false;  // a cut seed not tried again for want of time
  // One seed's chain within its budget; whether the budget cut it: no convergence gained, a
  // step of a word's chain stopped by the clock or not reached (the search seed: its PRM or
  // refinement stopped by the clock, or its budget used up), and the solve's own clock not run
  // out.
  const auto trySeed = [&](const Seed* seed) {
    std::optional<double> limit = deadline.left();
    if (budgeted) {
      log.budget_s = std::ldexp(seed == first ? first_budget : options.seed_time_s, log.round);
      limit = std::min(log.budget_s, limit.value_or(log.budget_s));
    }
    const double given = limit.value_or(std::numeric_limits<double>::infinity());
    log.time_given_s = given;
    granted.erase(seed);
    const ocp::Deadline within(Clock::now(), limit, options.stop);
    const bool converged_before = log.converged();
    const Clock::time_point t0 = Clock::now();
    bool unfinished = false;
    if (seed == nullptr) {
      // newton and ceres: the first route's refinement alone (their fallback, above).
      SeededSolveOptions search_options = options;
      if (!isTranscription(options.method)) {
        search_options.search_improvements = 0;
        search_options.search_improve_milestones = 0;
      }
      // The PRM's better route first (RouteOrder) after a convergence (a word's detour: the
      // search seed can only improve on a result) and in a retry (the clock cut the first
      // route's refinement: on davosdorf's Segway 3 it ran out of 10 s and of 20 s again, the
      // route 8,000 milestones on converges in 1.7 s).
      const RouteOrder route_order = log.converged() || log.round > 0
                                         ? RouteOrder::kImprovedFirst
                                         : RouteOrder::kFirstSolutionFirst;
      SeededSolution found =
          solveFromSearch(vehicle, problem, *map, search_options, within.left(), why, route_order);
      // Cut when its PRM or its refinement says the clock stopped it (a solve, or a step skipped
      // for lack of time: RefinementResult::time_limit_reached), or its whole budget is gone. A
      // chain that ended on its own ends the same again (the PRM's seed, the deterministic
      // solvers): not retried. Until 2026-12-07 any chain that used 80 % of its budget was
      // retried, repeating a 25 s refinement to the same verdict on davosdorf's Segway 3.
      unfinished = found.time_limit_reached || within.over();
      log.record(std::move(found), t0);
      if (log.round > 0) granted[seed] = given;
    } else {
      ChainProgress& done = progress[seed];
      const bool solved_before = done.solved, ipopt_ended_before = done.ipopt_ended;
      if (!done.solved) {
        SeededSolution result = attempt(vehicle, problem, map, options, seed, within.left());
        done.solved = !result.time_limit_reached;
        log.record(std::move(result), t0);
      }
      if (options.method == CoreMethod::kAuto && !log.converged() && !done.bridged) {
        done.bridged = !within.over() &&
                       bridgeThroughIpopt(vehicle, problem, map, options, *seed, within, done, log);
        unfinished = !done.bridged;
      }
      unfinished = unfinished || !done.solved;
      if (unfinished && done.solved == solved_before && done.ipopt_ended == ipopt_ended_before) {
        granted[seed] = given;  // no step ended on its own: a retry runs this chain again
      }
    }
    const bool gained = log.converged() && !converged_before;
    return budgeted && !gained && unfinished && !deadline.over();
  };
  while (!order.empty()) {
    std::vector<const Seed*> cut;
    // After a convergence in the first round the search seed comes after the words: a word
    // across a slope may beat the converged result where the PRM's class does not (davosdorf
    // point 3 of seed 17: 9.40 s from the RSL word, 9.75 s from the search seed).
    bool search_deferred = false;
    for (const Seed* seed : order) {
      if (deadline.over() && !log.empty()) break;
      if (seed == nullptr && log.round == 0 && log.converged()) {
        search_deferred = true;
        continue;
      }
      if (!wanted(seed)) continue;
      if (log.round > 0 && !moreTimeThanBefore(seed)) {
        starved = true;
        continue;
      }
      if (trySeed(seed)) cut.push_back(seed);
    }
    if (search_deferred && !deadline.over() && wanted(nullptr) && trySeed(nullptr)) {
      cut.push_back(nullptr);
    }
    if (log.converged() || deadline.over()) break;
    order = std::move(cut);
    ++log.round;
  }
  explainAnEndShortOfConvergence(deadline, !order.empty(), starved, log);
  if (log.empty()) {
    log.best().status = ocp::SolveStatus::kInfeasible;
    log.best().reason =
        "no seed: every Dubins word crosses an impassable cell or no data and no search seed was "
        "allowed";
  }
}

}  // namespace

double firstSeedBudget(const SeededSolveOptions& options) {
  return std::max(options.seed_time_s, options.first_seed_time_s);
}

SeededSolution seededSolutionOf(ocp::VerifiedTranscription result, std::string method,
                                std::string initial_guess) {
  SeededSolution out;
  out.status = result.status;
  out.reason = result.reason;
  out.method = std::move(method);
  out.initial_guess = std::move(initial_guess);
  out.verified = result.verified;
  out.verdict = result.verdict;
  out.history = result.history;
  out.iterations = result.iterations;
  out.total_time_ms = result.solve_time_ms;
  out.time_limit_reached = result.time_limit_reached;
  out.transcription = std::move(result);
  return out;
}

SeededSolution solveSeeded(const models::TerrainFollowingModel& vehicle,
                           const ocp::BoundaryValueProblem& problem,
                           const terrain::ElevationMap* map, const SeededSolveOptions& options) {
  const Clock::time_point started = Clock::now();
  const ocp::Deadline deadline(started, options.time_limit_s, options.stop);
  AttemptLog log(options.method, options.on_attempt);
  // A goal no trajectory can reach (boxed in by slopes, lethal or no-data cells): infeasible at
  // once, with the reason, instead of after every seed has spent its iterations.
  std::optional<models::GoalReachability> reachability =
      checkReachability(vehicle, problem, map, options, deadline);
  if (reachability && !reachability->reachable) {
    SeededSolution& out = log.best();
    out.status = ocp::SolveStatus::kInfeasible;
    out.reason = reachability->reason;
  } else if (options.initial_guess == InitialGuessKind::kFlat ||
             ocp::startMeetsGoal(problem, options.parametric.criteria)) {
    const Clock::time_point t0 = Clock::now();
    log.record(attemptFlat(vehicle, problem, map, options, deadline), t0);
  } else {
    solveFromSeeds(vehicle, problem, map, options, deadline, log);
  }
  SeededSolution best = std::move(log.best());
  best.reachability = std::move(reachability);
  best.total_time_ms = 1e3 * secondsSince(started);
  return best;
}

}  // namespace terratraj::refine
