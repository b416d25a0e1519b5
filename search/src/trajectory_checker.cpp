#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::search {

models::TrajectoryRequirements requirementsOf(const PlanningProblem& problem,
                                              const CheckTolerances& tolerances, bool endpoints) {
  models::TrajectoryRequirements r;
  r.map = problem.map;
  r.vehicle = problem.vehicle;
  r.limits = problem.limits;
  r.pitch_table = problem.pitch_table;
  r.roll_curvature_table = problem.roll_curvature_table;
  r.tolerances = tolerances;
  if (endpoints) {
    models::StartRequirement start;
    start.position = problem.start.position;
    start.v = problem.start.v;
    r.start = start;
    models::GoalRequirement goal;
    goal.position = problem.goal.position;
    goal.heading = problem.goal.heading;
    goal.v = problem.goal.v;
    goal.position_tolerance = problem.goal.position_tolerance;
    goal.heading_tolerance = problem.goal.heading_tolerance;
    goal.speed_tolerance = problem.goal.speed_tolerance;
    r.goal = goal;
  }
  return r;
}

CheckReport TrajectoryChecker::check(const models::Trajectory& trajectory,
                                     bool check_endpoints) const {
  return models::checkTrajectory(trajectory,
                                 requirementsOf(*problem_, tolerances_, check_endpoints));
}

}  // namespace terratraj::search
