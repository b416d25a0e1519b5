#include "terratraj/ocp/solution_verdict.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {

models::TrajectoryRequirements solveRequirements(const models::TerrainFollowingModel& vehicle,
                                                 const BoundaryValueProblem& problem,
                                                 const ConvergenceCriteria& criteria,
                                                 const terrain::ElevationMap* map) {
  models::TrajectoryRequirements r;
  r.map = map;
  r.vehicle = &vehicle;
  r.limits = problem.limits;
  r.pitch_table = problem.tables.pitch;
  r.roll_curvature_table = problem.tables.roll_curvature;
  r.segway = problem.tables.segway;
  models::StartRequirement start;
  start.position = {problem.start.x, problem.start.y};
  start.v = problem.start.v;
  r.start = start;
  models::GoalRequirement goal;
  goal.position = {problem.goal.x, problem.goal.y};
  goal.heading = problem.goal.heading;
  goal.v = problem.goal.v;
  goal.position_tolerance = criteria.position_m;
  goal.heading_tolerance = criteria.heading_rad;
  goal.speed_tolerance = 1e-3 * problem.limits.v_max + 1e-6;
  r.goal = goal;
  return r;
}

SolveStatus statusAfterVerdict(SolveStatus solver_status,
                               const models::TrajectoryVerdict& verdict) {
  if (solver_status != SolveStatus::kConverged) return solver_status;
  switch (verdict.failure) {
    case models::VerdictFailure::kNone:
      return SolveStatus::kConverged;
    case models::VerdictFailure::kCrossesMap:
    case models::VerdictFailure::kBreaksLimits:
      return SolveStatus::kInfeasible;
    case models::VerdictFailure::kMissesGoal:
    case models::VerdictFailure::kUnusable:
      return SolveStatus::kDiverged;
  }
  return SolveStatus::kDiverged;
}

std::pair<double, std::string> largestLimitViolation(const models::CheckReport& check) {
  std::pair<double, std::string> worst{0.0, ""};
  for (const models::CheckViolation& v : check.violations) {
    if (v.limit.rfind("goal_", 0) == 0 || v.limit.rfind("start_", 0) == 0) continue;
    if (worst.second.empty() || v.amount > worst.first) worst = {v.amount, v.limit};
  }
  return worst;
}

}  // namespace terratraj::ocp
