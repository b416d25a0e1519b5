#include "terratraj/ocp/trajectory_verifier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "terratraj/models/rover_integrator.hpp"
#include "terratraj/ocp/parametric_controls.hpp"
#include "terratraj/ocp/slope_dwell_integrand.hpp"

namespace terratraj::ocp {

namespace {

// v(t), omega(t): the start's speed and yaw rate plus the exact integral of the solution's
// interpolated controls (piecewise constant, linear, or quadratic on Hermite-Simpson
// intervals), node by node; independent of the solution's own v and omega.
class TranscribedControls final : public models::ControlProfile {
 public:
  TranscribedControls(const TranscriptionSolution& solution, const VehicleState& start)
      : solution_(solution) {
    const std::size_t intervals = solution.mesh.size() - 1;
    node_values_.resize(intervals + 1);
    node_values_[0] = Eigen::Vector2d(start.v, start.omega);
    for (std::size_t k = 0; k < intervals; ++k) {
      node_values_[k + 1] = node_values_[k] + integral(k, 1.0);
    }
  }
  int parameterCount() const override { return 0; }
  void evaluate(double t, double& v, double& omega, double*, double*) const override {
    const std::vector<double>& mesh = solution_.mesh;
    const double tau = std::clamp(t / solution_.final_time, 0.0, 1.0);
    const std::size_t k = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(
            std::upper_bound(mesh.begin(), mesh.end(), tau) - mesh.begin() - 1, 0)),
        mesh.size() - 2);
    const double s = (tau - mesh[k]) / (mesh[k + 1] - mesh[k]);
    const Eigen::Vector2d value = node_values_[k] + integral(k, s);
    v = value.x();
    omega = value.y();
  }

 private:
  // Integral of the controls over the first fraction s of interval k.
  Eigen::Vector2d integral(std::size_t k, double s) const {
    const TranscriptionSolution& x = solution_;
    const double h = x.final_time * (x.mesh[k + 1] - x.mesh[k]);
    if (x.scheme == TranscriptionScheme::kHermiteSimpson) {
      const Eigen::Vector2d a = x.points[2 * k].tail<2>(), m = x.points[2 * k + 1].tail<2>(),
                            b = x.points[2 * k + 2].tail<2>();
      const double s2 = s * s, s3 = s2 * s;
      return h * ((2.0 * s3 / 3.0 - 1.5 * s2 + s) * a - 4.0 * (s3 / 3.0 - s2 / 2.0) * m +
                  (2.0 * s3 / 3.0 - s2 / 2.0) * b);
    }
    const Eigen::Vector2d a = x.points[k].tail<2>(), b = x.points[k + 1].tail<2>();
    if (x.scheme == TranscriptionScheme::kMultipleShooting &&
        x.shooting_controls == ShootingControls::kPiecewiseConstant) {
      return h * s * a;
    }
    return h * (s * a + 0.5 * s * s * (b - a));
  }

  const TranscriptionSolution& solution_;
  std::vector<Eigen::Vector2d> node_values_;
};

// Speeds below this are rest [m/s]: their curvature omega / v is rounding noise.
constexpr double kRestSpeed = 1e-9;

// The integrator leaves the curvature of a sample at rest (v = 0) undefined (NaN), or computes
// it from rounding noise; a sample at rest gets v = omega = 0 and the curvature of its nearest
// sample in motion (0 when none moves), so that every column of the CSV is a number.
void fillCurvatureAtRest(models::Trajectory& trajectory) {
  std::vector<models::TrajectorySample>& s = trajectory.samples;
  for (models::TrajectorySample& sample : s) {
    if (std::abs(sample.v) < kRestSpeed && std::abs(sample.omega) < kRestSpeed) {
      sample.v = sample.omega = 0.0;
      sample.curvature = std::numeric_limits<double>::quiet_NaN();
    }
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (std::isfinite(s[i].curvature)) continue;
    double value = 0.0;
    for (std::size_t d = 1; d < s.size(); ++d) {
      if (i >= d && std::isfinite(s[i - d].curvature)) {
        value = s[i - d].curvature;
        break;
      }
      if (i + d < s.size() && std::isfinite(s[i + d].curvature)) {
        value = s[i + d].curvature;
        break;
      }
    }
    s[i].curvature = value;
  }
}

// Re-simulates `controls` for `tf` seconds and checks every sample with `check(sample)`, which
// folds violations into out.violation. Fills everything else in VerifiedTrajectory.
template <typename Check>
VerifiedTrajectory resimulate(const models::TerrainFollowingModel& vehicle,
                              const BoundaryValueProblem& problem,
                              const models::ControlProfile& controls, double tf,
                              const terrain::ElevationMap* map, const VerificationOptions& options,
                              VerifiedTrajectory& out, Check&& check) {
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
  fillCurvatureAtRest(out.trajectory);
  if (result.status != models::IntegrationStatus::kOk) {
    out.off_terrain = result.status == models::IntegrationStatus::kNoTerrain;
    out.message = std::string("re-simulation: ") + result.message +
                  " at t = " + std::to_string(result.t_reached) + " s, (" +
                  std::to_string(result.final_state.x()) + ", " +
                  std::to_string(result.final_state.y()) + ") m";
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
  const terrain::GridLayer* lethal = map != nullptr ? map->findLayer("lethal") : nullptr;
  for (const models::TrajectorySample& s : out.trajectory.samples) {
    out.max_abs_pitch = std::max(out.max_abs_pitch, std::abs(s.pitch));
    out.max_abs_roll = std::max(out.max_abs_roll, std::abs(s.roll));
    out.max_speed = std::max(out.max_speed, std::abs(s.v));
    check(s);
    if (lethal != nullptr && out.violation.limit != "lethal") {
      const std::optional<terrain::CellIndex> cell = map->geometry().cellAt({s.x, s.y});
      // A lethal cell is reported as a violation of 1 (no unit), whatever else is violated.
      if (cell && map->isLethal(*cell)) out.violation = {1.0, "lethal", s.t};
    }
  }
  return out;
}

}  // namespace

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
  const PathConstraints constraints(problem.limits, problem.tables);
  return resimulate(vehicle, problem, controls, controls.finalTime(), map, options, out,
                    [&](const models::TrajectorySample& s) {
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
                    });
}

VerifiedTrajectory verifyTranscriptionSolution(const TranscriptionModel& model,
                                               const TranscriptionSolution& solution,
                                               const terrain::ElevationMap* map,
                                               const VerificationOptions& options) {
  VerifiedTrajectory out;
  const BoundaryValueProblem& problem = model.problem();
  const bool hs = solution.scheme == TranscriptionScheme::kHermiteSimpson;
  const std::size_t intervals = solution.mesh.size() < 2 ? 0 : solution.mesh.size() - 1;
  if (intervals == 0 || !(solution.final_time > 0.0) ||
      solution.points.size() != (hs ? 2 * intervals + 1 : intervals + 1)) {
    out.message = "the solution is empty or inconsistent with its mesh";
    return out;
  }
  const TranscribedControls controls(solution, problem.start);
  PointEvaluation evaluation = model.makeEvaluation();
  models::AttitudeWorkspace workspace;
  double effort = 0.0, previous_t = 0.0, previous_u2 = 0.0;
  resimulate(model.kinematics().model(), problem, controls, solution.final_time, map, options, out,
             [&](const models::TrajectorySample& s) {
               const Eigen::Vector2d u = solution.controlsAt(s.t);
               PointVector w;
               w << s.x, s.y, s.heading, s.v, s.omega, u.x(), u.y();
               if (model.evaluate(w, workspace, evaluation) != models::AttitudeStatus::kOk) {
                 out.violation = {1.0, "no_terrain", s.t};
                 return;
               }
               evaluation.point.t = s.t;
               model.accumulateViolation(evaluation, out.violation);
               const double u2 = u.squaredNorm();
               if (s.t > 0.0) effort += 0.5 * (u2 + previous_u2) * (s.t - previous_t);
               previous_t = s.t;
               previous_u2 = u2;
             });
  out.cost += model.options().control_effort_weight * effort;
  if (out.ok) {
    // The goal speed and yaw rate, as re-integrated from the controls.
    double v = 0.0, omega = 0.0;
    controls.evaluate(solution.final_time, v, omega, nullptr, nullptr);
    out.terminal_speed_error = Eigen::Vector2d(v - problem.goal.v, omega - problem.goal.omega);
  }
  return out;
}

}  // namespace terratraj::ocp
