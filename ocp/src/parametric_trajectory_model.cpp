#include "terratraj/ocp/parametric_trajectory_model.hpp"

#include <cmath>
#include <vector>

namespace terratraj::ocp {
namespace {

models::IntegratorOptions withSensitivities(models::IntegratorOptions options, bool on) {
  options.sensitivities = on;
  return options;
}

const std::vector<double> kNoSamples;

}  // namespace

ParametricTrajectoryModel::ParametricTrajectoryModel(const models::TerrainFollowingModel& vehicle,
                                                     const BoundaryValueProblem& problem,
                                                     const ParametricModelOptions& options)
    : vehicle_(&vehicle),
      problem_(problem),
      options_(options),
      kinematics_(vehicle),
      plain_(kinematics_, withSensitivities(options.integrator, false)),
      with_sensitivities_(kinematics_, withSensitivities(options.integrator, true)),
      controls_(problem.start, problem.goal, problem.orders),
      slope_dwell_(problem.cost.alpha) {
  dv_dq_.resize(controls_.parameterCount());
  domega_dq_.resize(controls_.parameterCount());
  dv_dot_dq_.resize(controls_.parameterCount());
  domega_dot_dq_.resize(controls_.parameterCount());
}

bool ParametricTrajectoryModel::integrate(const Eigen::VectorXd& q, bool sensitivities,
                                          ParametricEvaluation& out,
                                          const std::vector<double>& sample_times) {
  const int n = parameterCount();
  out.status = models::IntegrationStatus::kOk;
  out.message.clear();
  if (q.size() != n || !q.allFinite()) {
    out.status = models::IntegrationStatus::kInvalidInput;
    out.message = "the control parameters are not finite";
    return false;
  }
  const double tf = q(finalTimeIndex());
  if (!(tf > 0.0)) {
    out.status = models::IntegrationStatus::kInvalidInput;
    out.message = "final time t_f = " + std::to_string(tf) + " s is not positive";
    return false;
  }
  controls_.setParameters(q);
  const bool dwell = problem_.cost.kind == CostKind::kSlopeDwell;
  const Eigen::Vector3d initial(problem_.start.x, problem_.start.y, problem_.start.heading);
  models::RoverIntegrator& integrator = sensitivities ? with_sensitivities_ : plain_;
  integrator.integrate(initial, controls_, tf, sample_times, out.integration,
                       dwell ? &slope_dwell_ : nullptr);
  ++integrations_;
  if (out.integration.status != models::IntegrationStatus::kOk) {
    out.status = out.integration.status;
    out.message =
        out.integration.message + " at t = " + std::to_string(out.integration.t_reached) + " s";
    return false;
  }
  out.terminal_state = out.integration.final_state;
  out.terminal_error =
      out.terminal_state - Eigen::Vector3d(problem_.goal.x, problem_.goal.y, problem_.goal.heading);
  out.terminal_error.z() = wrapAngle(out.terminal_error.z());
  out.running_cost = dwell ? out.integration.integral : 0.0;
  out.cost = tf + out.running_cost;
  if (!sensitivities) return true;

  // c(q) = s(t_f(q); q): d c / d q = S(t_f) + s'(t_f) e_tf'.
  double v = 0.0, omega = 0.0;
  controls_.evaluate(tf, v, omega, nullptr, nullptr);
  const models::AttitudeStatus status =
      kinematics_.rates(out.terminal_state, v, omega, terminal_workspace_, terminal_rates_);
  if (status != models::AttitudeStatus::kOk) {
    out.status = models::IntegrationStatus::kNoTerrain;
    out.message = std::string("attitude at the final state: ") + models::attitudeStatusName(status);
    return false;
  }
  out.jacobian = out.integration.sensitivity;
  out.jacobian.col(finalTimeIndex()) += terminal_rates_.rate;
  out.gradient.setZero(n);
  double terminal_integrand = 0.0;
  if (dwell) {
    out.gradient = out.integration.integral_sensitivity.transpose();
    terminal_integrand = slope_dwell_.evaluate(tf, terminal_rates_, v, omega, nullptr, nullptr);
  }
  out.gradient(finalTimeIndex()) += 1.0 + terminal_integrand;
  return true;
}

bool ParametricTrajectoryModel::evaluate(const Eigen::VectorXd& q, DerivativeMode mode,
                                         ParametricEvaluation& out) {
  switch (mode) {
    case DerivativeMode::kNone:
      return integrate(q, false, out, kNoSamples);
    case DerivativeMode::kSensitivity:
      return integrate(q, true, out, kNoSamples);
    case DerivativeMode::kFiniteDifference:
      return integrate(q, false, out, kNoSamples) && finiteDifferences(q, out);
  }
  return false;
}

bool ParametricTrajectoryModel::evaluateWithPath(const Eigen::VectorXd& q, bool derivatives,
                                                 const std::vector<double>& tau,
                                                 ParametricEvaluation& out, PathEvaluation& path) {
  const int n = parameterCount();
  const int itf = finalTimeIndex();
  const double tf = q.size() == n ? q(itf) : 0.0;
  sample_times_.resize(tau.size());
  for (std::size_t i = 0; i < tau.size(); ++i) sample_times_[i] = std::min(tau[i] * tf, tf);
  if (!integrate(q, derivatives, out, sample_times_)) return false;
  path.points.resize(tau.size());
  path.derivatives.resize(derivatives ? tau.size() : 0);
  for (std::size_t i = 0; i < tau.size(); ++i) {
    const models::TrajectorySample& sample = out.integration.samples.samples[i];
    PathPoint& point = path.points[i];
    point.t = sample.t;
    point.state = Eigen::Vector3d(sample.x, sample.y, sample.heading);
    controls_.evaluate(point.t, point.v, point.omega, dv_dq_.data(), domega_dq_.data());
    const ControlRates rates = controls_.rates(point.t, dv_dot_dq_.data(), domega_dot_dq_.data());
    point.v_dot = rates.v_dot;
    point.omega_dot = rates.omega_dot;
    const models::AttitudeStatus status =
        kinematics_.rates(point.state, point.v, point.omega, terminal_workspace_, terminal_rates_);
    if (status != models::AttitudeStatus::kOk) {
      out.status = models::IntegrationStatus::kNoTerrain;
      out.message = std::string("attitude along the path: ") + models::attitudeStatusName(status);
      return false;
    }
    point.attitude = terminal_rates_.attitude;
    if (!derivatives) continue;
    // Points sit at fixed tau: d/dt_f = (d/dt_f at fixed t) + tau d/dt.
    Eigen::Matrix<double, kPathVariables, Eigen::Dynamic>& d = path.derivatives[i];
    d.resize(kPathVariables, n);
    d.topRows<3>() =
        out.integration.sample_sensitivity.middleRows(3 * static_cast<Eigen::Index>(i), 3);
    d.block(0, itf, 3, 1) += tau[i] * terminal_rates_.rate;
    d.row(3) = dv_dq_.transpose();
    d.row(4) = domega_dq_.transpose();
    d.row(5) = dv_dot_dq_.transpose();
    d.row(6) = domega_dot_dq_.transpose();
    d(3, itf) = 0.0;  // v(tau) does not depend on t_f
    d(4, itf) = 0.0;
    d(5, itf) = -rates.v_dot / tf;  // v' = p'(tau) / t_f
    d(6, itf) = -rates.omega_dot / tf;
  }
  return true;
}

bool ParametricTrajectoryModel::finiteDifferences(const Eigen::VectorXd& q,
                                                  ParametricEvaluation& out) {
  const int n = parameterCount();
  const double e = options_.finite_difference_step;
  out.jacobian.resize(3, n);
  out.gradient.resize(n);
  Eigen::VectorXd qk = q;
  for (int k = 0; k < n; ++k) {
    qk(k) = q(k) + e;
    if (!integrate(qk, false, scratch_, kNoSamples)) {
      out.status = scratch_.status;
      out.message = "finite difference: " + scratch_.message;
      return false;
    }
    qk(k) = q(k);
    Eigen::Vector3d dc = scratch_.terminal_state - out.terminal_state;
    dc.z() = wrapAngle(dc.z());
    out.jacobian.col(k) = dc / e;
    out.gradient(k) = (scratch_.cost - out.cost) / e;
  }
  controls_.setParameters(q);
  return true;
}

bool ParametricTrajectoryModel::lagrangianHessian(const Eigen::VectorXd& q,
                                                  const Eigen::Vector3d& lambda,
                                                  DerivativeMode mode, double h,
                                                  Eigen::MatrixXd& hessian) {
  const int n = parameterCount();
  hessian.resize(n, n);
  Eigen::VectorXd qk = q;
  if (mode == DerivativeMode::kSensitivity) {
    if (!integrate(q, true, scratch2_, kNoSamples)) return false;
    const Eigen::VectorXd base = scratch2_.gradient + scratch2_.jacobian.transpose() * lambda;
    for (int k = 0; k < n; ++k) {
      qk(k) = q(k) + h;
      if (!integrate(qk, true, scratch_, kNoSamples)) return false;
      qk(k) = q(k);
      hessian.col(k) = (scratch_.gradient + scratch_.jacobian.transpose() * lambda - base) / h;
    }
  } else {
    // 004_... eq. 11: second forward differences of the Lagrangian's value. The terminal
    // heading is unwrapped relative to the base point so that differences never jump by 2 pi.
    if (!integrate(q, false, scratch2_, kNoSamples)) return false;
    const Eigen::Vector3d base_state = scratch2_.terminal_state;
    const double base_cost = scratch2_.cost;
    const auto lagrangian_difference = [&](const ParametricEvaluation& at) {
      Eigen::Vector3d dc = at.terminal_state - base_state;
      dc.z() = wrapAngle(dc.z());
      return at.cost - base_cost + lambda.dot(dc);
    };
    Eigen::VectorXd single(n);
    for (int k = 0; k < n; ++k) {
      qk(k) = q(k) + h;
      if (!integrate(qk, false, scratch_, kNoSamples)) return false;
      qk(k) = q(k);
      single(k) = lagrangian_difference(scratch_);
    }
    for (int k = 0; k < n; ++k) {
      for (int m = k; m < n; ++m) {
        qk(k) += h;
        qk(m) += h;
        if (!integrate(qk, false, scratch_, kNoSamples)) return false;
        qk(k) = q(k);
        qk(m) = q(m);
        hessian(k, m) = (lagrangian_difference(scratch_) - single(k) - single(m)) / (h * h);
        hessian(m, k) = hessian(k, m);
      }
    }
  }
  hessian = 0.5 * (hessian + hessian.transpose()).eval();
  controls_.setParameters(q);
  return true;
}

}  // namespace terratraj::ocp
