#pragma once
// The contract's verdict on a plan. Every solution's trajectory, as its CSV will hold it, is
// judged by models::judgeTrajectory() against the planning problem (its map, vehicle, limits,
// tables, start, and goal region); a plan keeps only the solutions that pass and is `solved`
// only when one does. Every planner's solve() ends with these.

#include "terratraj/models/trajectory_checker.hpp"
#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/planning_problem.hpp"

namespace terratraj::search {

/// Judges `solution` against `requirements` (requirementsOf(problem)): when it passes, its
/// `check` is filled and it is appended to result.solutions (true); else it is recorded in
/// result.rejected with the reason (false). Never throws (except std::bad_alloc).
bool admitSolution(const models::TrajectoryRequirements& requirements, PlanSolution solution,
                   PlanResult& result);

/// Sets the status from the admitted solutions: kSolved with `trajectory`, `best_cost_s` and
/// `length_m` of the first; else kNoSolution, with a reason naming what broke when solutions
/// were found but all rejected (the planner's own reason is kept otherwise).
void concludePlan(PlanResult& result);

/// The answer when the start already lies in the goal region (every planner, docs/usage.md):
/// one solution, the one-row trajectory at the start (cost 0), judged by admitSolution(), then
/// concludePlan().
void planStartInGoal(const PlanningProblem& problem, PlanResult& result);

/// admitSolution() for every solution of a kSolved `result` (every planner fills `solutions`),
/// then concludePlan().
void applyPlanVerdict(const PlanningProblem& problem, PlanResult& result);

}  // namespace terratraj::search
