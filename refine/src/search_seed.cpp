#include "terratraj/refine/search_seed.hpp"

#include <algorithm>
#include <sstream>

#include "terratraj/models/segway_lookups.hpp"
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

SeededSolution solveFromSearch(const models::TerrainFollowingModel& vehicle,
                               const ocp::BoundaryValueProblem& problem,
                               const terrain::ElevationMap& map, const SeededSolveOptions& options,
                               std::optional<double> time_left_s, const std::string& why) {
  SeededSolution out;
  out.method = "collocation";
  out.initial_guess = "search (prm first solution)";
  search::PlanningProblem query(map, vehicle);
  query.limits = problem.limits;
  query.pitch_table = problem.tables.pitch;
  // The Segway's speed bound by slope, as the search takes it: a seed it can drive.
  std::optional<models::PitchSpeedTable> segway_table;
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
  if (const std::optional<std::string> invalid = query.validate()) {
    out.status = ocp::SolveStatus::kInfeasible;
    out.reason = "no search seed: " + *invalid;
    return out;
  }
  search::PrmOptions prm_options;
  prm_options.seed = options.search_seed;
  search::KinodynamicPrm prm(query, prm_options);
  const double budget = searchSeedBudget(options, time_left_s);
  const search::PlanResult plan = prm.solve(
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
       << " s)";
  out.initial_guess = seed.str();
  search::ReferenceFrameOptions frame_options;
  frame_options.anchor = 0.5 * (query.start.position + query.goal.position);
  const search::ReferenceFrames frames =
      search::ReferenceFrames::build(map, terrain::findObstacleClusters(map), frame_options);
  refine::RefinementOptions refine;
  refine.method = options.method == CoreMethod::kShooting ? refine::RefineMethod::kShooting
                                                          : refine::RefineMethod::kCollocation;
  refine.parametric = options.parametric;
  refine.transcription = options.transcription.transcription;
  refine.transcription.linear_controls = true;
  refine.transcription.intervals = refine.min_intervals;  // set per candidate by its length
  refine.max_intervals = std::max(refine.min_intervals, options.transcription.max_intervals);
  refine.stop = options.stop;
  if (time_left_s) refine.time_limit_s = std::max(0.0, *time_left_s - 1e-3 * plan.planning_time_ms);
  const refine::CandidateRefiner refiner(query, problem, frames, refine);
  refine::RefinementResult r = refiner.refine(plan.solutions.front().trajectory);
  out.method = std::string(refine::refineMethodName(r.method)) + " (refining the search seed)";
  out.status = r.returned_candidate ? ocp::SolveStatus::kDiverged : r.status;
  out.reason = r.reason;
  out.verified = std::move(r.verified);
  out.verdict = std::move(r.verdict);
  out.history = std::move(r.history);
  out.iterations = r.iterations;
  out.time_limit_reached = out.status != ocp::SolveStatus::kConverged &&
                           (r.time_limit_reached ||
                            (refine.time_limit_s && r.solve_time_ms >= 1e3 * *refine.time_limit_s));
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
