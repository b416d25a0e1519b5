#pragma once
// Start == goal, one behaviour for every command (docs/usage.md, "Verdicts"): when the start
// already meets the goal within the tolerances, there is nothing to drive, and the answer is
// the one-row trajectory at the start (duration 0, cost 0), which the verdict then checks like
// any other. A goal at the start's position with another heading or speed is not this case: it
// is a turn (a loop for a vehicle that cannot turn in place), solved like any problem.

#include <optional>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp {

/// Whether the start meets the goal: position within criteria.position_m, heading within
/// criteria.heading_rad, speed within 1e-3 v_max + 1e-6 m/s and yaw rate within 1e-3
/// omega_max + 1e-6 rad/s.
bool startMeetsGoal(const BoundaryValueProblem& problem, const ConvergenceCriteria& criteria);

/// The one-row trajectory at the start: t = 0, the pose, the attitude `vehicle` rests in, the
/// start's speed and yaw rate (curvature omega / v, 0 at rest). std::nullopt when the vehicle
/// cannot rest there.
std::optional<models::Trajectory> startOnlyTrajectory(const models::TerrainFollowingModel& vehicle,
                                                      const BoundaryValueProblem& problem);

}  // namespace terratraj::ocp
