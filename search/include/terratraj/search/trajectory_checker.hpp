#pragma once
// TrajectoryChecker: models::checkTrajectory() (the independent re-check behind every verdict)
// against a PlanningProblem: its map, vehicle, limits, tables, start and goal region.

#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/trajectory_checker.hpp"
#include "terratraj/search/planning_problem.hpp"

namespace terratraj::search {

using models::CheckReport;
using models::CheckTolerances;
using models::CheckViolation;

/// The requirements of `problem`: its map, vehicle, limits and tables; with `endpoints`, its
/// start (position within 1e-6 m, speed within 1e-6 m/s) and goal region.
models::TrajectoryRequirements requirementsOf(const PlanningProblem& problem,
                                              const CheckTolerances& tolerances = {},
                                              bool endpoints = true);

/// Checks trajectories against one problem.
class TrajectoryChecker {
 public:
  /// `problem` must outlive the checker.
  explicit TrajectoryChecker(const PlanningProblem& problem, const CheckTolerances& tolerances = {})
      : problem_(&problem), tolerances_(tolerances) {}

  /// Checks the limits and the map; with `check_endpoints`, also that the first sample is the
  /// start and that the last lies in the goal region.
  CheckReport check(const models::Trajectory& trajectory, bool check_endpoints = true) const;

 private:
  const PlanningProblem* problem_;
  CheckTolerances tolerances_;
};

}  // namespace terratraj::search
