#include "terratraj/refine/search_seed.hpp"

#include <algorithm>
#include <sstream>

#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/ocp/deadline.hpp"
#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace terratraj::refine {

double searchSeedBudget(const SeededSolveOptions& options, std::optional<double> time_left_s) {
  const double budget = options.search_time_s.value_or(kDefaultSearchTimeS);
  return time_left_s ? std::min(budget, 0.5 * *time_left_s) : budget;
}

namespace {

// The PRM's query for `problem`: its limits and tables (the Segway's speed bound by slope, as
// the search takes it: a seed it can drive, held in `segway_table`), its start and goal.
search::PlanningProblem searchQuery(const models::TerrainFollowingModel& vehicle,
                                    const ocp::BoundaryValueProblem& problem,
                                    const terrain::ElevationMap& map,
                                    std::optional<models::PitchSpeedTable>& segway_table) {
  search::PlanningProblem query(map, vehicle);
  query.limits = problem.limits;
  query.pitch_table = problem.tables.pitch;
  if (problem.tables.segway != nullptr) {
    segway_table = models::slopeSpeedTable(problem.tables.segway->bounds, problem.tables.pitch);
    query.pitch_table = &*segway_table;
  }
  query.roll_curvature_table = problem.tables.roll_curvature;
  query.start.position = {problem.start.x, problem.start.y};
  query.start.heading = problem.start.heading;
  query.start.v = problem.start.v;
  query.start.curvature = problem.start.v > 0.0 ? problem.start.omega / problem.start.v : 0.0;
  query.goal.position = {problem.goal.x, problem.goal.y};
  query.goal.heading = problem.goal.heading;
  query.goal.v = problem.goal.v;
  return query;
}

refine::RefinementOptions refinementOptions(const SeededSolveOptions& options) {
  refine::RefinementOptions refine;
  refine.method = options.method == CoreMethod::kShooting ? refine::RefineMethod::kShooting
                                                          : refine::RefineMethod::kCollocation;
  refine.parametric = options.parametric;
  refine.transcription = options.transcription.transcription;
  refine.transcription.linear_controls = true;
  refine.transcription.intervals = refine.min_intervals;  // set per candidate by its length
  refine.max_intervals = std::max(refine.min_intervals, options.transcription.max_intervals);
  refine.stop = options.stop;
  return refine;
}

// Whether a refinement ended without a verified trajectory on its own: run again from the same
// route it would end the same, so only another route can change the verdict.
bool failedOnItsOwn(const refine::RefinementResult& r, const ocp::Deadline& within) {
  return (r.status != ocp::SolveStatus::kConverged || r.returned_candidate) &&
         !r.time_limit_reached && !within.over();
}

}  // namespace

SeededSolution solveFromSearch(const models::TerrainFollowingModel& vehicle,
                               const ocp::BoundaryValueProblem& problem,
                               const terrain::ElevationMap& map, const SeededSolveOptions& options,
                               std::optional<double> time_left_s, const std::string& why,
                               RouteOrder order) {
  const ocp::Deadline within(time_left_s, options.stop);
  SeededSolution out;
  out.method = "collocation";
  out.initial_guess = "search (prm first solution)";
  std::optional<models::PitchSpeedTable> segway_table;
  const search::PlanningProblem query = searchQuery(vehicle, problem, map, segway_table);
  if (const std::optional<std::string> invalid = query.validate()) {
    out.status = ocp::SolveStatus::kInfeasible;
    out.reason = "no search seed: " + *invalid;
    return out;
  }
  search::PrmOptions prm_options;
  prm_options.seed = options.search_seed;
  search::KinodynamicPrm prm(query, prm_options);
  const double budget = searchSeedBudget(options, time_left_s);
  search::PlanResult plan = prm.solve(
      search::TerminationCondition::timeLimit(budget).stopAtFirstSolution().stopFlag(options.stop));
  if (plan.status != search::PlanStatus::kSolved) {
    std::ostringstream reason;
    reason << why << ", and the PRM found no path in " << budget << " s (" << plan.reason
           << "): the goal may be unreachable";
    out.status = ocp::SolveStatus::kInfeasible;
    out.reason = reason.str();
    out.time_limit_reached = budget < options.search_time_s.value_or(kDefaultSearchTimeS) &&
                             !(options.stop != nullptr && options.stop->load());
    return out;
  }
  std::ostringstream seed;
  seed.precision(3);
  seed << "search (prm first solution, " << plan.solutions.front().length_m << " m, found in "
       << 1e-3 * plan.first_solution_ms.value_or(plan.planning_time_ms) << " s of " << budget
       << " s";
  // After a refinement that failed on its own, the PRM continues for search_improve_milestones
  // (cheap next to a refinement: 0.03-0.6 s) and its better route is refined (RouteOrder: the
  // first solution first, or the route after the first continuation).
  std::size_t milestones = 0;        // continued for so far
  std::size_t route_milestones = 0;  // when the best route was found (0: the first solution)
  const auto improveRoute = [&]() {
    if (options.search_improve_milestones == 0 || within.over()) return false;
    const double cost_before = plan.best_cost_s;
    const std::optional<double> left = within.left();
    search::PlanResult more =
        prm.solve(search::TerminationCondition::timeLimit(left ? 0.5 * *left : budget)
                      .maxIterations(options.search_improve_milestones)
                      .stopFlag(options.stop));
    milestones += options.search_improve_milestones;
    if (more.solutions.empty() || !(more.best_cost_s < cost_before)) return false;
    plan = std::move(more);
    route_milestones = milestones;
    return true;
  };
  const auto routeName = [&]() {
    std::ostringstream name;
    name.precision(3);
    name << seed.str();
    if (route_milestones > 0) {
      name << "; its best route after " << route_milestones << " more milestones, "
           << plan.solutions.front().length_m << " m";
    }
    name << ")";
    return name.str();
  };
  if (order == RouteOrder::kImprovedFirst) improveRoute();
  search::ReferenceFrameOptions frame_options;
  frame_options.anchor = 0.5 * (query.start.position + query.goal.position);
  const search::ReferenceFrames frames =
      search::ReferenceFrames::build(map, terrain::findObstacleClusters(map), frame_options);
  refine::RefinementOptions refine = refinementOptions(options);
  const auto refineRoute = [&](const models::Trajectory& route) {
    if (within.left()) refine.time_limit_s = *within.left();
    const refine::CandidateRefiner refiner(query, problem, frames, refine);
    return refiner.refine(route);
  };
  std::string route = routeName();
  refine::RefinementResult r = refineRoute(plan.solutions.front().trajectory);
  const bool first_cut = r.time_limit_reached ||
                         (refine.time_limit_s && r.solve_time_ms >= 1e3 * *refine.time_limit_s);
  // A failed refinement of the route: the PRM continues, and a better route is refined.
  std::ostringstream earlier;
  for (int k = 0; k < options.search_improvements && failedOnItsOwn(r, within) && improveRoute();
       ++k) {
    earlier << "; before it, " << route << ": " << ocp::solveStatusName(r.status) << " ("
            << r.reason << ")";
    route = routeName();
    r = refineRoute(plan.solutions.front().trajectory);
  }
  out.initial_guess = route;
  out.method = std::string(refine::refineMethodName(r.method)) + " (refining the search seed)";
  out.status = r.returned_candidate ? ocp::SolveStatus::kDiverged : r.status;
  out.reason = r.reason;
  if (out.status != ocp::SolveStatus::kConverged) out.reason += earlier.str();
  out.verified = std::move(r.verified);
  out.verdict = std::move(r.verdict);
  out.history = std::move(r.history);
  out.iterations = r.iterations;
  // Retried with a larger budget (solveSeeded) only when the clock cut the first route's
  // refinement: a retry starts the chain again, and the continuations only use what is left.
  out.time_limit_reached = out.status != ocp::SolveStatus::kConverged && first_cut;
  if (r.transcription) {
    ocp::VerifiedTranscription t;
    t.solution = std::move(*r.transcription);
    t.status = out.status;
    t.reason = out.reason;
    out.transcription = std::move(t);
  }
  return out;
}

}  // namespace terratraj::refine
