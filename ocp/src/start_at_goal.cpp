#include "terratraj/ocp/start_at_goal.hpp"

#include <cmath>

namespace terratraj::ocp {

bool startMeetsGoal(const BoundaryValueProblem& problem, const ConvergenceCriteria& criteria) {
  const VehicleState& a = problem.start;
  const VehicleState& b = problem.goal;
  return std::hypot(b.x - a.x, b.y - a.y) <= criteria.position_m &&
         std::abs(wrapAngle(b.heading - a.heading)) <= criteria.heading_rad &&
         std::abs(b.v - a.v) <= 1e-3 * problem.limits.v_max + 1e-6 &&
         std::abs(b.omega - a.omega) <= 1e-3 * problem.limits.omega_max + 1e-6;
}

std::optional<models::Trajectory> startOnlyTrajectory(const models::TerrainFollowingModel& vehicle,
                                                      const BoundaryValueProblem& problem) {
  const VehicleState& s = problem.start;
  models::AttitudeWorkspace workspace;
  models::AttitudeResult attitude;
  if (vehicle.compute({s.x, s.y, s.heading}, workspace, attitude) != models::AttitudeStatus::kOk) {
    return std::nullopt;
  }
  models::Trajectory trajectory;
  trajectory.has_column.fill(true);
  models::TrajectorySample sample;
  sample.t = 0.0;
  sample.x = s.x;
  sample.y = s.y;
  sample.z = attitude.attitude.z;
  sample.heading = s.heading;
  sample.roll = attitude.attitude.roll;
  sample.pitch = attitude.attitude.pitch;
  sample.v = s.v;
  sample.omega = s.omega;
  sample.curvature = s.v > 0.0 ? s.omega / s.v : 0.0;
  trajectory.samples.push_back(sample);
  return trajectory;
}

}  // namespace terratraj::ocp
