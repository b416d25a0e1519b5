#include "terratraj/models/rover_integrator.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

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
  } else {
    result.sensitivity.resize(0, 0);
  }
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

// One explicit step of the fixed-step scheme from (t, x, S) over h, with its sensitivity.
// Buffers come from FixedStepWork so that a step allocates nothing.
struct FixedStepWork {
  RoverRates rates;
  Eigen::VectorXd dv_dq, domega_dq;
  Eigen::MatrixXd stage_s, k_s[4], b;
  void resize(int nq) {
    dv_dq.resize(nq);
    domega_dq.resize(nq);
    stage_s.resize(3, nq);
    b.resize(3, nq);
    for (Eigen::MatrixXd& k : k_s) k.resize(3, nq);
  }
};

}  // namespace

class FixedStepScheme {
 public:
  FixedStepScheme(const RoverKinematics& kinematics, AttitudeWorkspace& workspace,
                  const ControlProfile& controls, bool sensitivities, FixedStepWork& work,
                  long& evaluations)
      : kinematics_(kinematics),
        workspace_(workspace),
        controls_(controls),
        sensitivities_(sensitivities),
        work_(work),
        evaluations_(evaluations) {}

  // Rates k (and, with sensitivities, K = A S + B) at (t, x, S).
  AttitudeStatus stage(double t, const Eigen::Vector3d& x, const Eigen::MatrixXd* s,
                       Eigen::Vector3d& k, Eigen::MatrixXd* k_s) {
    double v = 0.0, omega = 0.0;
    controls_.evaluate(t, v, omega, sensitivities_ ? work_.dv_dq.data() : nullptr,
                       sensitivities_ ? work_.domega_dq.data() : nullptr);
    ++evaluations_;
    const AttitudeStatus status = kinematics_.rates(x, v, omega, workspace_, work_.rates);
    if (status != AttitudeStatus::kOk) return status;
    k = work_.rates.rate;
    if (sensitivities_) {
      k_s->noalias() = work_.rates.d_state * (*s);
      k_s->noalias() += work_.rates.d_input.col(0) * work_.dv_dq.transpose();
      k_s->noalias() += work_.rates.d_input.col(1) * work_.domega_dq.transpose();
    }
    return AttitudeStatus::kOk;
  }

  AttitudeStatus euler(double t, double h, Eigen::Vector3d& x, Eigen::MatrixXd& s) {
    Eigen::Vector3d k;
    const AttitudeStatus status = stage(t, x, &s, k, &work_.k_s[0]);
    if (status != AttitudeStatus::kOk) return status;
    x += h * k;
    if (sensitivities_) s += h * work_.k_s[0];
    return status;
  }

  AttitudeStatus rk4(double t, double h, Eigen::Vector3d& x, Eigen::MatrixXd& s) {
    Eigen::Vector3d k[4];
    const double offsets[4] = {0.0, 0.5 * h, 0.5 * h, h};
    for (int i = 0; i < 4; ++i) {
      Eigen::Vector3d xi = x;
      if (i > 0) {
        xi += offsets[i] * k[i - 1];
        if (sensitivities_) work_.stage_s = s + offsets[i] * work_.k_s[i - 1];
      } else if (sensitivities_) {
        work_.stage_s = s;
      }
      const AttitudeStatus status = stage(t + offsets[i], xi, &work_.stage_s, k[i], &work_.k_s[i]);
      if (status != AttitudeStatus::kOk) return status;
    }
    x += h / 6.0 * (k[0] + 2.0 * k[1] + 2.0 * k[2] + k[3]);
    if (sensitivities_) {
      s += h / 6.0 * (work_.k_s[0] + 2.0 * work_.k_s[1] + 2.0 * work_.k_s[2] + work_.k_s[3]);
    }
    return AttitudeStatus::kOk;
  }

  AttitudeStatus step(IntegrationMethod method, double t, double h, Eigen::Vector3d& x,
                      Eigen::MatrixXd& s) {
    return method == IntegrationMethod::kEuler ? euler(t, h, x, s) : rk4(t, h, x, s);
  }

 private:
  const RoverKinematics& kinematics_;
  AttitudeWorkspace& workspace_;
  const ControlProfile& controls_;
  bool sensitivities_;
  FixedStepWork& work_;
  long& evaluations_;
};

void RoverIntegrator::integrate(const Eigen::Vector3d& initial, const ControlProfile& controls,
                                double duration, const std::vector<double>& sample_times,
                                IntegrationResult& result) {
  const int nq = controls.parameterCount();
  detail::prepareResult(initial, nq, options_.sensitivities, sample_times.size(), result);
  if (!detail::validateRequest(duration, sample_times, result)) return;
  workspace_.has_warm_start = false;
  if (options_.method == IntegrationMethod::kCvodes) {
    integrateCvodes(initial, controls, duration, sample_times, result);
  } else {
    integrateFixedStep(initial, controls, duration, sample_times, result);
  }
}

void RoverIntegrator::integrateFixedStep(const Eigen::Vector3d& initial,
                                         const ControlProfile& controls, double duration,
                                         const std::vector<double>& sample_times,
                                         IntegrationResult& result) {
  const int nq = controls.parameterCount();
  FixedStepWork work;
  work.resize(nq);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(3, options_.sensitivities ? nq : 0);
  Eigen::MatrixXd sample_s = s;
  FixedStepScheme scheme(kinematics_, workspace_, controls, options_.sensitivities, work,
                         result.rhs_evaluations);
  const long n = std::max(1L, static_cast<long>(std::ceil(duration / options_.step - 1e-9)));
  const double h = duration / static_cast<double>(n);
  Eigen::Vector3d x = initial;
  std::size_t next_sample = 0;
  RoverRates sample_rates;
  // Records every sample time in [t, t + h): a partial step of the same scheme from (t, x).
  const auto record_samples_until = [&](double t, double t_end, bool last) -> AttitudeStatus {
    while (next_sample < sample_times.size() &&
           (sample_times[next_sample] < t_end || (last && sample_times[next_sample] <= t_end))) {
      const double ts = sample_times[next_sample];
      Eigen::Vector3d xs = x;
      sample_s = s;
      if (ts > t) {
        const AttitudeStatus status = scheme.step(options_.method, t, ts - t, xs, sample_s);
        if (status != AttitudeStatus::kOk) return status;
      }
      double v = 0.0, omega = 0.0;
      controls.evaluate(ts, v, omega, nullptr, nullptr);
      const AttitudeStatus status = kinematics_.rates(xs, v, omega, workspace_, sample_rates);
      if (status != AttitudeStatus::kOk) return status;
      result.samples.samples.push_back(
          detail::makeSample(ts, xs, v, omega, sample_rates.attitude.attitude));
      ++next_sample;
    }
    return AttitudeStatus::kOk;
  };
  for (long i = 0; i < n; ++i) {
    const double t = duration * static_cast<double>(i) / static_cast<double>(n);
    AttitudeStatus status = record_samples_until(t, t + h, false);
    if (status == AttitudeStatus::kOk) status = scheme.step(options_.method, t, h, x, s);
    if (status != AttitudeStatus::kOk) {
      result.status = detail::fromAttitudeStatus(status);
      result.message = std::string("attitude: ") + attitudeStatusName(status);
      result.t_reached = t;
      result.final_state = x;
      return;
    }
    ++result.steps;
  }
  result.t_reached = duration;
  result.final_state = x;
  if (options_.sensitivities) result.sensitivity = s;
  const AttitudeStatus status = record_samples_until(duration, duration, true);
  if (status != AttitudeStatus::kOk) {
    result.status = detail::fromAttitudeStatus(status);
    result.message = std::string("attitude: ") + attitudeStatusName(status);
  }
}

}  // namespace terratraj::models
