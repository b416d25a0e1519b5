#include "terratraj/ocp/trajectory_verifier.hpp"

#include <algorithm>
#include <cmath>

#include "terratraj/models/rover_integrator.hpp"
#include "terratraj/ocp/parametric_controls.hpp"
#include "terratraj/ocp/slope_dwell_integrand.hpp"

namespace terratraj::ocp {

VerifiedTrajectory verifyParametricSolution(const models::TerrainFollowingModel& vehicle,
                                            const BoundaryValueProblem& problem,
                                            const Eigen::VectorXd& q,
                                            const terrain::ElevationMap* map,
                                            const VerificationOptions& options) {
  VerifiedTrajectory out;
  ParametricControls controls(problem.start, problem.goal, problem.orders);
  if (q.size() != controls.parameterCount() || !q.allFinite() ||
      !(q(controls.finalTimeIndex()) > 0.0)) {
    out.message = "the controls are not valid (wrong size, NaN or t_f <= 0)";
    return out;
  }
  controls.setParameters(q);
  const double tf = controls.finalTime();
  models::IntegratorOptions integrator_options;
  integrator_options.relative_tolerance = options.relative_tolerance;
  integrator_options.absolute_tolerance = options.absolute_tolerance;
  const models::RoverKinematics kinematics(vehicle);
  models::RoverIntegrator integrator(kinematics, integrator_options);
  const SlopeDwellIntegrand dwell(1.0);
  models::IntegrationResult result;
  const Eigen::Vector3d initial(problem.start.x, problem.start.y, problem.start.heading);
  integrator.integrate(initial, controls, tf,
                       models::uniformSampleTimes(tf, std::max(options.sample_dt, 1e-4)), result,
                       &dwell);
  out.trajectory = result.samples;
  if (result.status != models::IntegrationStatus::kOk) {
    out.message = std::string("re-simulation: ") + result.message +
                  " at t = " + std::to_string(result.t_reached) + " s";
    return out;
  }
  out.ok = true;
  out.final_time = tf;
  out.terminal_error =
      result.final_state - Eigen::Vector3d(problem.goal.x, problem.goal.y, problem.goal.heading);
  out.terminal_error.z() = wrapAngle(out.terminal_error.z());
  out.slope_dwell = result.integral;
  out.cost = tf + (problem.cost.kind == CostKind::kSlopeDwell ? problem.cost.alpha * result.integral
                                                              : 0.0);
  out.length = out.trajectory.planarLength();

  const PathConstraints constraints(problem.limits, problem.tables);
  const terrain::GridLayer* lethal = map != nullptr ? map->findLayer("lethal") : nullptr;
  models::AttitudeWorkspace workspace;
  for (const models::TrajectorySample& s : out.trajectory.samples) {
    out.max_abs_pitch = std::max(out.max_abs_pitch, std::abs(s.pitch));
    out.max_abs_roll = std::max(out.max_abs_roll, std::abs(s.roll));
    out.max_speed = std::max(out.max_speed, std::abs(s.v));
    PathPoint point;
    point.t = s.t;
    point.state = Eigen::Vector3d(s.x, s.y, s.heading);
    point.v = s.v;
    point.omega = s.omega;
    const ControlRates rates = controls.rates(s.t, nullptr, nullptr);
    point.v_dot = rates.v_dot;
    point.omega_dot = rates.omega_dot;
    point.attitude.attitude = {s.z, s.roll, s.pitch};
    constraints.accumulateViolation(point, out.violation);
    if (lethal != nullptr && out.violation.limit != "lethal") {
      const std::optional<terrain::CellIndex> cell = map->geometry().cellAt({s.x, s.y});
      // A lethal cell is reported as a violation of 1 (no unit), whatever else is violated.
      if (cell && map->isLethal(*cell)) out.violation = {1.0, "lethal", s.t};
    }
  }
  return out;
}

}  // namespace terratraj::ocp
