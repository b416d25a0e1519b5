#include "terratraj/search/plan_verdict.hpp"

#include <sstream>

#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::search {

bool admitSolution(const models::TrajectoryRequirements& requirements, PlanSolution solution,
                   PlanResult& result) {
  models::TrajectoryVerdict verdict = models::judgeTrajectory(solution.trajectory, requirements);
  if (!verdict.passes()) {
    result.rejected.push_back({solution.cost_s, solution.homotopy, verdict.reason});
    return false;
  }
  solution.check = std::move(verdict.check);
  result.solutions.push_back(std::move(solution));
  return true;
}

void concludePlan(PlanResult& result) {
  if (!result.solutions.empty()) {
    const PlanSolution& best = result.solutions.front();
    result.status = PlanStatus::kSolved;
    result.trajectory = best.trajectory;
    result.best_cost_s = best.cost_s;
    result.length_m = best.length_m;
    result.reason.clear();
    return;
  }
  result.status = PlanStatus::kNoSolution;
  result.trajectory = models::Trajectory();
  if (result.rejected.empty()) return;
  std::ostringstream reason;
  reason << "every solution found (" << result.rejected.size()
         << ") fails the independent check of its trajectory; the first: "
         << result.rejected.front().reason;
  result.reason = reason.str();
}

void planStartInGoal(const PlanningProblem& problem, PlanResult& result) {
  models::Trajectory here;
  here.has_column.fill(true);
  models::AttitudeWorkspace workspace;
  models::AttitudeResult attitude;
  const PlannerState& s = problem.start;
  if (problem.vehicle->compute({s.position.x(), s.position.y(), s.heading}, workspace, attitude) ==
      models::AttitudeStatus::kOk) {
    models::TrajectorySample sample;
    sample.t = 0.0;
    sample.x = s.position.x();
    sample.y = s.position.y();
    sample.z = attitude.attitude.z;
    sample.heading = s.heading;
    sample.roll = attitude.attitude.roll;
    sample.pitch = attitude.attitude.pitch;
    sample.v = s.v;
    sample.curvature = s.curvature;
    sample.omega = s.v * s.curvature;
    here.samples.push_back(sample);
  }
  PlanSolution solution;
  solution.trajectory = std::move(here);
  solution.proven_optimal = true;
  result.first_solution_ms = 0.0;
  result.first_solution_cost_s = 0.0;
  admitSolution(requirementsOf(problem), std::move(solution), result);
  concludePlan(result);
}

void applyPlanVerdict(const PlanningProblem& problem, PlanResult& result) {
  if (result.status != PlanStatus::kSolved) return;
  std::vector<PlanSolution> found = std::move(result.solutions);
  result.solutions.clear();
  const models::TrajectoryRequirements requirements = requirementsOf(problem);
  for (PlanSolution& solution : found) admitSolution(requirements, std::move(solution), result);
  concludePlan(result);
}

}  // namespace terratraj::search
