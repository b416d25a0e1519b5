#include "terratraj/models/rover_integrator.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "rover_integrator_internal.hpp"

namespace terratraj::models {

const char* integrationMethodName(IntegrationMethod method) {
  switch (method) {
    case IntegrationMethod::kEuler:
      return "euler";
    case IntegrationMethod::kRk4:
      return "rk4";
    case IntegrationMethod::kCvodes:
      return "cvodes";
  }
  return "unknown";
}

const char* integrationStatusName(IntegrationStatus status) {
  switch (status) {
    case IntegrationStatus::kOk:
      return "ok";
    case IntegrationStatus::kNoTerrain:
      return "no_terrain";
    case IntegrationStatus::kNoContact:
      return "no_contact";
    case IntegrationStatus::kSolverFailure:
      return "solver_failure";
    case IntegrationStatus::kInvalidInput:
      return "invalid_input";
  }
  return "unknown";
}

std::vector<double> uniformSampleTimes(double duration, double dt) {
  std::vector<double> times;
  if (!(duration >= 0.0) || !(dt > 0.0)) return times;
  const long n = static_cast<long>(std::ceil(duration / dt - 1e-9));
  times.reserve(static_cast<std::size_t>(n) + 1);
  for (long i = 0; i < n; ++i) times.push_back(static_cast<double>(i) * dt);
  times.push_back(duration);
  return times;
}

namespace detail {

IntegrationStatus fromAttitudeStatus(AttitudeStatus status) {
  return status == AttitudeStatus::kNoTerrain ? IntegrationStatus::kNoTerrain
                                              : IntegrationStatus::kNoContact;
}

TrajectorySample makeSample(double t, const Eigen::Vector3d& state, double v, double omega,
                            const Attitude& attitude) {
  const double curvature = v != 0.0 ? omega / v : std::numeric_limits<double>::quiet_NaN();
  return {t, state.x(), state.y(), attitude.z, state.z(), attitude.roll, attitude.pitch,
          v, omega,     curvature};
}

bool validateRequest(double duration, const std::vector<double>& sample_times,
                     IntegrationResult& result) {
  std::string problem;
  if (!(duration >= 0.0) || !std::isfinite(duration)) {
    problem = "duration must be a finite number >= 0";
  } else {
    double previous = -std::numeric_limits<double>::infinity();
    for (const double t : sample_times) {
      if (!(t >= 0.0 && t <= duration) || !(t >= previous)) {
        problem = "sample times must be ascending and within [0, duration]";
        break;
      }
      previous = t;
    }
  }
  if (problem.empty()) return true;
  result.status = IntegrationStatus::kInvalidInput;
  result.message = problem;
  return false;
}

void prepareResult(const Eigen::Vector3d& initial, int parameter_count, bool sensitivities,
                   std::size_t sample_count, IntegrationResult& result) {
  result.status = IntegrationStatus::kOk;
  result.message.clear();
  result.t_reached = 0.0;
  result.final_state = initial;
  if (sensitivities) {
    result.sensitivity.setZero(3, parameter_count);
    result.sample_sensitivity.setZero(3 * static_cast<Eigen::Index>(sample_count), parameter_count);
    result.integral_sensitivity.setZero(parameter_count);
  } else {
    result.sensitivity.resize(0, 0);
    result.sample_sensitivity.resize(0, 0);
    result.integral_sensitivity.resize(0);
  }
  result.integral = 0.0;
  result.samples.samples.clear();
  result.samples.samples.reserve(sample_count);
  result.samples.has_column.fill(sample_count > 0);
  result.samples.ignored_columns.clear();
  result.steps = 0;
  result.rhs_evaluations = 0;
}

void validateOptions(const IntegratorOptions& options) {
  if (!(options.step > 0.0) || !(options.relative_tolerance > 0.0) ||
      !(options.absolute_tolerance > 0.0) || options.max_steps <= 0) {
    throw std::invalid_argument("RoverIntegrator: step, tolerances and max_steps must be positive");
  }
}

}  // namespace detail

namespace {

// The state a fixed-step scheme advances: (x, y, heading), the running integral, and with
// sensitivities their derivatives by q.
struct FixedStepState {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  Eigen::MatrixXd s;  // 3 x nq
  double integral = 0.0;
  Eigen::RowVectorXd integral_s;  // 1 x nq
  void resize(int nq) {
    s.setZero(3, nq);
    integral_s.setZero(nq);
  }
};

// Buffers for one step, sized once so that a step allocates nothing.
struct FixedStepWork {
  RoverRates rates;
  Eigen::VectorXd dv_dq, domega_dq;
  FixedStepState stage_state, k[4];
  void resize(int nq) {
    dv_dq.resize(nq);
    domega_dq.resize(nq);
    stage_state.resize(nq);
    for (FixedStepState& ki : k) ki.resize(nq);
  }
};

}  // namespace

// One explicit step (Euler or RK4) of the state, the running integral and their sensitivities.
class FixedStepScheme {
 public:
  FixedStepScheme(const RoverKinematics& kinematics, AttitudeWorkspace& workspace,
                  const ControlProfile& controls, const RunningIntegrand* integrand,
                  bool sensitivities, FixedStepWork& work, long& evaluations)
      : kinematics_(kinematics),
        workspace_(workspace),
        controls_(controls),
        integrand_(integrand),
        sensitivities_(sensitivities),
        work_(work),
        evaluations_(evaluations) {}

  // Rates of every part of `at` (time t) into `rate`.
  AttitudeStatus stage(double t, const FixedStepState& at, FixedStepState& rate) {
    double v = 0.0, omega = 0.0;
    controls_.evaluate(t, v, omega, sensitivities_ ? work_.dv_dq.data() : nullptr,
                       sensitivities_ ? work_.domega_dq.data() : nullptr);
    ++evaluations_;
    const AttitudeStatus status = kinematics_.rates(at.x, v, omega, workspace_, work_.rates);
    if (status != AttitudeStatus::kOk) return status;
    rate.x = work_.rates.rate;
    if (sensitivities_) {
      rate.s.noalias() = work_.rates.d_state * at.s;
      rate.s.noalias() += work_.rates.d_input.col(0) * work_.dv_dq.transpose();
      rate.s.noalias() += work_.rates.d_input.col(1) * work_.domega_dq.transpose();
    }
    if (integrand_ != nullptr) {
      Eigen::Vector3d dl_dstate;
      Eigen::Vector2d dl_dinput;
      rate.integral =
          integrand_->evaluate(t, work_.rates, v, omega, sensitivities_ ? &dl_dstate : nullptr,
                               sensitivities_ ? &dl_dinput : nullptr);
      if (sensitivities_) {
        rate.integral_s.noalias() = dl_dstate.transpose() * at.s;
        rate.integral_s.noalias() += dl_dinput(0) * work_.dv_dq.transpose();
        rate.integral_s.noalias() += dl_dinput(1) * work_.domega_dq.transpose();
      }
    }
    return AttitudeStatus::kOk;
  }

  AttitudeStatus step(IntegrationMethod method, double t, double h, FixedStepState& y) {
    if (method == IntegrationMethod::kEuler) {
      const AttitudeStatus status = stage(t, y, work_.k[0]);
      if (status == AttitudeStatus::kOk) axpy(h, work_.k[0], y);
      return status;
    }
    const double offsets[4] = {0.0, 0.5 * h, 0.5 * h, h};
    for (int i = 0; i < 4; ++i) {
      copy(y, work_.stage_state);
      if (i > 0) axpy(offsets[i], work_.k[i - 1], work_.stage_state);
      const AttitudeStatus status = stage(t + offsets[i], work_.stage_state, work_.k[i]);
      if (status != AttitudeStatus::kOk) return status;
    }
    const double weights[4] = {h / 6.0, h / 3.0, h / 3.0, h / 6.0};
    for (int i = 0; i < 4; ++i) axpy(weights[i], work_.k[i], y);
    return AttitudeStatus::kOk;
  }

 private:
  // y += a * k over the parts in use.
  void axpy(double a, const FixedStepState& k, FixedStepState& y) const {
    y.x += a * k.x;
    if (sensitivities_) y.s += a * k.s;
    if (integrand_ != nullptr) {
      y.integral += a * k.integral;
      if (sensitivities_) y.integral_s += a * k.integral_s;
    }
  }
  void copy(const FixedStepState& from, FixedStepState& to) const {
    to.x = from.x;
    if (sensitivities_) to.s = from.s;
    to.integral = from.integral;
    if (sensitivities_ && integrand_ != nullptr) to.integral_s = from.integral_s;
  }

  const RoverKinematics& kinematics_;
  AttitudeWorkspace& workspace_;
  const ControlProfile& controls_;
  const RunningIntegrand* integrand_;
  bool sensitivities_;
  FixedStepWork& work_;
  long& evaluations_;
};

void RoverIntegrator::integrate(const Eigen::Vector3d& initial, const ControlProfile& controls,
                                double duration, const std::vector<double>& sample_times,
                                IntegrationResult& result, const RunningIntegrand* integrand) {
  const int nq = controls.parameterCount();
  detail::prepareResult(initial, nq, options_.sensitivities, sample_times.size(), result);
  if (!detail::validateRequest(duration, sample_times, result)) return;
  workspace_.has_warm_start = false;
  if (options_.method == IntegrationMethod::kCvodes) {
    integrateCvodes(initial, controls, duration, sample_times, integrand, result);
  } else {
    integrateFixedStep(initial, controls, duration, sample_times, integrand, result);
  }
}

void RoverIntegrator::integrateFixedStep(const Eigen::Vector3d& initial,
                                         const ControlProfile& controls, double duration,
                                         const std::vector<double>& sample_times,
                                         const RunningIntegrand* integrand,
                                         IntegrationResult& result) {
  const bool sensitivities = options_.sensitivities;
  const int nq = sensitivities ? controls.parameterCount() : 0;
  FixedStepWork work;
  work.resize(nq);
  FixedStepState y, at_sample;
  y.resize(nq);
  at_sample.resize(nq);
  y.x = initial;
  FixedStepScheme scheme(kinematics_, workspace_, controls, integrand, sensitivities, work,
                         result.rhs_evaluations);
  const long n = std::max(1L, static_cast<long>(std::ceil(duration / options_.step - 1e-9)));
  const double h = duration / static_cast<double>(n);
  std::size_t next_sample = 0;
  RoverRates sample_rates;
  // Records every sample time in [t, t + h): a partial step of the same scheme from (t, y).
  const auto record_samples_until = [&](double t, double t_end, bool last) -> AttitudeStatus {
    while (next_sample < sample_times.size() &&
           (sample_times[next_sample] < t_end || (last && sample_times[next_sample] <= t_end))) {
      const double ts = sample_times[next_sample];
      at_sample.x = y.x;
      if (sensitivities) at_sample.s = y.s;
      if (ts > t) {
        const AttitudeStatus status = scheme.step(options_.method, t, ts - t, at_sample);
        if (status != AttitudeStatus::kOk) return status;
      }
      double v = 0.0, omega = 0.0;
      controls.evaluate(ts, v, omega, nullptr, nullptr);
      const AttitudeStatus status =
          kinematics_.rates(at_sample.x, v, omega, workspace_, sample_rates);
      if (status != AttitudeStatus::kOk) return status;
      result.samples.samples.push_back(
          detail::makeSample(ts, at_sample.x, v, omega, sample_rates.attitude.attitude));
      if (sensitivities)
        result.sample_sensitivity.middleRows(3 * static_cast<Eigen::Index>(next_sample), 3) =
            at_sample.s;
      ++next_sample;
    }
    return AttitudeStatus::kOk;
  };
  const auto finish = [&](double t_reached) {
    result.t_reached = t_reached;
    result.final_state = y.x;
    result.integral = y.integral;
    if (sensitivities) {
      result.sensitivity = y.s;
      if (integrand != nullptr) result.integral_sensitivity = y.integral_s;
    }
  };
  const std::optional<std::chrono::steady_clock::time_point>& deadline = options_.deadline;
  for (long i = 0; i < n; ++i) {
    const double t = duration * static_cast<double>(i) / static_cast<double>(n);
    if (deadline && (i & 63) == 63 && std::chrono::steady_clock::now() > *deadline) {
      result.status = IntegrationStatus::kSolverFailure;
      result.message = "fixed step: stopped at the time limit after " + std::to_string(i) +
                       " steps at t = " + std::to_string(t) + " s";
      finish(t);
      return;
    }
    AttitudeStatus status = record_samples_until(t, t + h, false);
    if (status == AttitudeStatus::kOk) status = scheme.step(options_.method, t, h, y);
    if (status != AttitudeStatus::kOk) {
      result.status = detail::fromAttitudeStatus(status);
      result.message = std::string("attitude: ") + attitudeStatusName(status);
      finish(t);
      return;
    }
    ++result.steps;
  }
  finish(duration);
  const AttitudeStatus status = record_samples_until(duration, duration, true);
  if (status != AttitudeStatus::kOk) {
    result.status = detail::fromAttitudeStatus(status);
    result.message = std::string("attitude: ") + attitudeStatusName(status);
  }
}

}  // namespace terratraj::models
