// The CVODES part of RoverIntegrator: forward integration with forward sensitivities.
#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rover_integrator_internal.hpp"
#include "terratraj/models/rover_integrator.hpp"

namespace terratraj::models {
namespace {

// Index of the running cost's integral in the CVODES state (x, y, heading, cost). The cost is
// a state, under the same error test, rather than a CVODES quadrature: CVODES 6.4's quadrature
// sensitivities read uninitialised memory with the Adams method (the gradient depended on the
// heap's contents), and without error control the integral was not smooth in the parameters.
constexpr int kCostState = 3;
// What the C callbacks need. Exceptions never cross them: nothing here throws.
struct CallbackData {
  const RoverKinematics* kinematics = nullptr;
  const ControlProfile* controls = nullptr;
  const RunningIntegrand* integrand = nullptr;
  AttitudeWorkspace* workspace = nullptr;
  RoverRates rates;
  double v = 0.0, omega = 0.0;
  Eigen::VectorXd dv_dq, domega_dq;
  // The point `rates` was computed at: CVODES evaluates the state and sensitivity
  // right-hand sides at the same (t, y), and the attitude is the expensive part.
  bool cached = false;
  double cached_t = 0.0;
  Eigen::Vector3d cached_y = Eigen::Vector3d::Zero();
  AttitudeStatus failure = AttitudeStatus::kOk;
  long evaluations = 0;
  std::array<char, 256> last_error{};  // CVODES's last error message (fixed size: no allocation)
};

// Keeps CVODES's messages off stderr: the last error becomes part of the result's message.
void recordCvodesError(int error_code, const char* module, const char* function, char* message,
                       void* user_data) {
  if (error_code > 0) return;  // warnings (e.g. "t + h = t") are not reported
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  std::snprintf(data.last_error.data(), data.last_error.size(), "%s %s: %s", module, function,
                message);
}

// Rates at (t, y) into data.rates (reused when the point is the one last evaluated).
bool evaluateRates(CallbackData& data, realtype t, N_Vector y) {
  const Eigen::Map<const Eigen::Vector3d> state(N_VGetArrayPointer(y));
  if (data.cached && data.cached_t == t && data.cached_y == state) return true;
  data.controls->evaluate(t, data.v, data.omega, nullptr, nullptr);
  ++data.evaluations;
  const AttitudeStatus status =
      data.kinematics->rates(state, data.v, data.omega, *data.workspace, data.rates);
  if (status != AttitudeStatus::kOk) {
    data.failure = status;
    data.cached = false;
    return false;
  }
  data.cached = true;
  data.cached_t = t;
  data.cached_y = state;
  return true;
}

// The running cost, when there is one, is the fourth state (kCostState).
int roverRhs(realtype t, N_Vector y, N_Vector ydot, void* user_data) {
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  if (!evaluateRates(data, t, y)) return -1;  // unrecoverable: the vehicle cannot be placed there
  double* rate = N_VGetArrayPointer(ydot);
  Eigen::Map<Eigen::Vector3d> state_rate(rate);
  state_rate = data.rates.rate;
  if (data.integrand != nullptr) {
    rate[kCostState] =
        data.integrand->evaluate(t, data.rates, data.v, data.omega, nullptr, nullptr);
  }
  return 0;
}

int roverSensitivityRhs(int ns, realtype t, N_Vector y, N_Vector /*ydot*/, N_Vector* ys,
                        N_Vector* ys_dot, void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/) {
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  if (!evaluateRates(data, t, y)) return -1;
  double v = 0.0, omega = 0.0;
  data.controls->evaluate(t, v, omega, data.dv_dq.data(), data.domega_dq.data());
  Eigen::Vector3d dl_dstate = Eigen::Vector3d::Zero();
  Eigen::Vector2d dl_dinput = Eigen::Vector2d::Zero();
  if (data.integrand != nullptr) {
    data.integrand->evaluate(t, data.rates, v, omega, &dl_dstate, &dl_dinput);
  }
  for (int i = 0; i < ns; ++i) {
    const Eigen::Map<const Eigen::Vector3d> s(N_VGetArrayPointer(ys[i]));
    double* s_dot = N_VGetArrayPointer(ys_dot[i]);
    Eigen::Map<Eigen::Vector3d> state_dot(s_dot);
    state_dot = data.rates.d_state * s + data.rates.d_input.col(0) * data.dv_dq(i) +
                data.rates.d_input.col(1) * data.domega_dq(i);
    if (data.integrand != nullptr) {
      s_dot[kCostState] =
          dl_dstate.dot(s) + dl_dinput(0) * data.dv_dq(i) + dl_dinput(1) * data.domega_dq(i);
    }
  }
  return 0;
}

std::string flagName(int flag) {
  char* name = CVodeGetReturnFlagName(flag);
  std::string text = name != nullptr ? name : "unknown";
  std::free(name);
  return text;
}

}  // namespace

// CVODES memory for one integrator: created on first use, re-initialised on every call, and
// re-created only when the number of sensitivity parameters changes.
class RoverIntegrator::CvodesSession {
 public:
  CvodesSession(const IntegratorOptions& options, int parameter_count, bool with_cost)
      : parameter_count_(parameter_count),
        with_cost_(with_cost),
        state_size_(with_cost ? 4 : 3),
        max_steps_(options.max_steps),
        deadline_(options.deadline) {
    ok_ = SUNContext_Create(nullptr, &context_) == 0;
    if (!ok_) return;
    y_ = N_VNew_Serial(state_size_, context_);
    memory_ = CVodeCreate(CV_ADAMS, context_);
    ok_ = y_ != nullptr && memory_ != nullptr;
    if (!ok_) return;
    N_VConst(0.0, y_);
    // No CVodeSetMaxNumSteps: advance() takes one step per CVode call and enforces max_steps.
    ok_ = CVodeInit(memory_, roverRhs, 0.0, y_) == CV_SUCCESS &&
          CVodeSStolerances(memory_, options.relative_tolerance, options.absolute_tolerance) ==
              CV_SUCCESS &&
          CVodeSetUserData(memory_, &data_) == CV_SUCCESS &&
          CVodeSetErrHandlerFn(memory_, recordCvodesError, &data_) == CV_SUCCESS;
    if (!ok_) return;
    solver_ = SUNNonlinSol_FixedPoint(y_, 0, context_);
    ok_ = solver_ != nullptr && CVodeSetNonlinearSolver(memory_, solver_) == CV_SUCCESS;
    if (!ok_ || !options.sensitivities || parameter_count_ == 0) return;
    ys_ = N_VCloneVectorArray(parameter_count_, y_);
    ok_ = ys_ != nullptr;
    if (!ok_) return;
    for (int i = 0; i < parameter_count_; ++i) N_VConst(0.0, ys_[i]);
    std::vector<realtype> abs_tolerances(static_cast<std::size_t>(parameter_count_),
                                         options.absolute_tolerance);
    ok_ = CVodeSensInit(memory_, parameter_count_, CV_SIMULTANEOUS, roverSensitivityRhs, ys_) ==
              CV_SUCCESS &&
          CVodeSensSStolerances(memory_, options.relative_tolerance, abs_tolerances.data()) ==
              CV_SUCCESS &&
          CVodeSetSensErrCon(memory_, options.sensitivity_error_control ? SUNTRUE : SUNFALSE) ==
              CV_SUCCESS;
    if (!ok_) return;
    sensitivity_solver_ = SUNNonlinSol_FixedPointSens(parameter_count_ + 1, y_, 0, context_);
    ok_ = sensitivity_solver_ != nullptr &&
          CVodeSetNonlinearSolverSensSim(memory_, sensitivity_solver_) == CV_SUCCESS;
    data_.dv_dq.resize(parameter_count_);
    data_.domega_dq.resize(parameter_count_);
  }

  ~CvodesSession() {
    if (ys_ != nullptr) N_VDestroyVectorArray(ys_, parameter_count_);
    if (memory_ != nullptr) CVodeFree(&memory_);
    if (sensitivity_solver_ != nullptr) SUNNonlinSolFree(sensitivity_solver_);
    if (solver_ != nullptr) SUNNonlinSolFree(solver_);
    if (y_ != nullptr) N_VDestroy(y_);
    if (context_ != nullptr) SUNContext_Free(&context_);
  }
  CvodesSession(const CvodesSession&) = delete;
  CvodesSession& operator=(const CvodesSession&) = delete;

  bool ok() const { return ok_; }
  /// Whether this session serves a call with these settings.
  bool matches(int parameter_count, bool with_cost) const {
    return parameter_count_ == parameter_count && with_cost_ == with_cost;
  }

  void run(const RoverKinematics& kinematics, AttitudeWorkspace& workspace,
           const Eigen::Vector3d& initial, const ControlProfile& controls,
           const RunningIntegrand* integrand, double duration,
           const std::vector<double>& sample_times, IntegrationResult& result) {
    data_.kinematics = &kinematics;
    data_.controls = &controls;
    data_.integrand = integrand;
    data_.cached = false;
    data_.workspace = &workspace;
    data_.failure = AttitudeStatus::kOk;
    data_.evaluations = 0;
    data_.last_error[0] = '\0';
    N_VConst(0.0, y_);
    Eigen::Map<Eigen::Vector3d>(N_VGetArrayPointer(y_)) = initial;
    const bool with_sensitivities = ys_ != nullptr;
    // CVODES takes a failed evaluation inside its corrector as recoverable and retries a
    // shorter step: where the solution itself leaves the terrain it would shrink the step past
    // what double precision can advance (1e-14 s at 11 s on the gully, a million steps). A
    // step shorter than 1e-12 of the duration (at least 1e-12 s) ends the run instead, with
    // the placement's failure as the reason.
    if (CVodeReInit(memory_, 0.0, y_) != CV_SUCCESS ||
        CVodeSetMinStep(memory_, 1e-12 * std::max(1.0, duration)) != CV_SUCCESS ||
        CVodeSetStopTime(memory_, duration) != CV_SUCCESS) {
      fail(result, IntegrationStatus::kSolverFailure, "CVODES re-initialisation failed");
      return;
    }
    if (with_sensitivities) {
      for (int i = 0; i < parameter_count_; ++i) N_VConst(0.0, ys_[i]);
      if (CVodeSensReInit(memory_, CV_SIMULTANEOUS, ys_) != CV_SUCCESS) {
        fail(result, IntegrationStatus::kSolverFailure,
             "CVODES sensitivity re-initialisation failed");
        return;
      }
    }
    // One internal step at a time (CV_ONE_STEP, never past the stop time), dense output at the
    // sample times: the last accepted step is always known, for reports after a failure.
    realtype t_internal = 0.0;
    last_good_time_ = 0.0;
    last_good_state_ = initial;
    steps_taken_ = 0;
    for (const double ts : sample_times) {
      if (!advance(ts, t_internal, result)) return;
      // Always interpolate: y_ may hold an earlier sample, not the state at t_internal.
      if (ts > 0.0 && CVodeGetDky(memory_, ts, 0, y_) != CV_SUCCESS) {
        fail(result, IntegrationStatus::kSolverFailure, "CVodeGetDky failed");
        return;
      }
      if (ts == 0.0) Eigen::Map<Eigen::Vector3d>(N_VGetArrayPointer(y_)) = initial;
      recordSample(kinematics, workspace, controls, ts, result);
      if (result.status != IntegrationStatus::kOk) return;
      if (with_sensitivities && ts > 0.0) {
        if (CVodeGetSensDky(memory_, ts, 0, ys_) != CV_SUCCESS) {
          fail(result, IntegrationStatus::kSolverFailure, "CVodeGetSensDky failed");
          return;
        }
        const Eigen::Index row = 3 * static_cast<Eigen::Index>(result.samples.samples.size() - 1);
        for (int i = 0; i < parameter_count_; ++i) {
          result.sample_sensitivity.block<3, 1>(row, i) =
              Eigen::Map<const Eigen::Vector3d>(N_VGetArrayPointer(ys_[i]));
        }
      }
    }
    if (!advance(duration, t_internal, result)) return;
    if (duration > 0.0 && CVodeGetDky(memory_, duration, 0, y_) != CV_SUCCESS) {
      fail(result, IntegrationStatus::kSolverFailure, "CVodeGetDky failed");
      return;
    }
    result.t_reached = duration;
    result.final_state =
        duration > 0.0 ? Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(N_VGetArrayPointer(y_)))
                       : initial;
    if (with_sensitivities && duration > 0.0) {
      if (CVodeGetSensDky(memory_, duration, 0, ys_) != CV_SUCCESS) {
        fail(result, IntegrationStatus::kSolverFailure, "CVodeGetSensDky failed");
        return;
      }
      for (int i = 0; i < parameter_count_; ++i) {
        result.sensitivity.col(i) = Eigen::Map<const Eigen::Vector3d>(N_VGetArrayPointer(ys_[i]));
      }
    }
    if (with_cost_ && duration > 0.0) {
      result.integral = N_VGetArrayPointer(y_)[kCostState];
      if (with_sensitivities) {
        for (int i = 0; i < parameter_count_; ++i) {
          result.integral_sensitivity(i) = N_VGetArrayPointer(ys_[i])[kCostState];
        }
      }
    }
    finishCounters(result);
  }

 private:
  // Steps until the internal time reaches t_out. On failure, reports the last accepted step.
  bool advance(double t_out, realtype& t_internal, IntegrationResult& result) {
    // A stop at the last accepted step, with the reason.
    const auto stop = [&](const std::string& why) {
      result.t_reached = last_good_time_;
      result.final_state = last_good_state_;
      fail(result, IntegrationStatus::kSolverFailure, why);
      return false;
    };
    while (t_internal < t_out) {
      if (deadline_ && (steps_taken_ & 63) == 0 && std::chrono::steady_clock::now() > *deadline_) {
        return stop("CVODES: stopped at the time limit after " + std::to_string(steps_taken_) +
                    " internal steps");
      }
      if (++steps_taken_ > max_steps_) {
        return stop("CVODES: CV_TOO_MUCH_WORK (more than max_steps = " +
                    std::to_string(max_steps_) + " internal steps)");
      }
      const int flag = CVode(memory_, t_out, y_, &t_internal, CV_ONE_STEP);
      if (flag < 0) {
        result.t_reached = last_good_time_;
        result.final_state = last_good_state_;
        if (data_.failure != AttitudeStatus::kOk) {
          fail(result, detail::fromAttitudeStatus(data_.failure),
               std::string("attitude: ") + attitudeStatusName(data_.failure));
        } else {
          fail(result, IntegrationStatus::kSolverFailure,
               "CVODES: " + flagName(flag) + " (" + data_.last_error.data() + ")");
        }
        return false;
      }
      last_good_time_ = t_internal;
      last_good_state_ = Eigen::Map<const Eigen::Vector3d>(N_VGetArrayPointer(y_));
      // A failed evaluation CVODES recovered from (a trial step beyond where the vehicle can be
      // placed, retried shorter) is not this run's failure.
      data_.failure = AttitudeStatus::kOk;
    }
    return true;
  }

  void recordSample(const RoverKinematics& kinematics, AttitudeWorkspace& workspace,
                    const ControlProfile& controls, double ts, IntegrationResult& result) {
    const Eigen::Map<const Eigen::Vector3d> state(N_VGetArrayPointer(y_));
    double v = 0.0, omega = 0.0;
    controls.evaluate(ts, v, omega, nullptr, nullptr);
    const AttitudeStatus status = kinematics.rates(state, v, omega, workspace, sample_rates_);
    if (status != AttitudeStatus::kOk) {
      fail(result, detail::fromAttitudeStatus(status),
           std::string("attitude: ") + attitudeStatusName(status));
      return;
    }
    result.samples.samples.push_back(
        detail::makeSample(ts, state, v, omega, sample_rates_.attitude.attitude));
  }

  void fail(IntegrationResult& result, IntegrationStatus status, const std::string& message) {
    result.status = status;
    result.message = message;
    finishCounters(result);
  }

  void finishCounters(IntegrationResult& result) {
    long steps = 0;
    CVodeGetNumSteps(memory_, &steps);
    result.steps = steps;
    result.rhs_evaluations = data_.evaluations;
  }

  int parameter_count_;
  bool with_cost_;
  int state_size_;  // 3, or 4 with the running cost's integral
  bool ok_ = false;
  SUNContext context_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector* ys_ = nullptr;
  void* memory_ = nullptr;
  SUNNonlinearSolver solver_ = nullptr;
  SUNNonlinearSolver sensitivity_solver_ = nullptr;
  CallbackData data_;
  RoverRates sample_rates_;
  long max_steps_;
  std::optional<std::chrono::steady_clock::time_point> deadline_;
  long steps_taken_ = 0;
  double last_good_time_ = 0.0;
  Eigen::Vector3d last_good_state_ = Eigen::Vector3d::Zero();
};

RoverIntegrator::RoverIntegrator(const RoverKinematics& kinematics,
                                 const IntegratorOptions& options)
    : kinematics_(kinematics), options_(options) {
  detail::validateOptions(options);
}

RoverIntegrator::~RoverIntegrator() = default;

void RoverIntegrator::integrateCvodes(const Eigen::Vector3d& initial,
                                      const ControlProfile& controls, double duration,
                                      const std::vector<double>& sample_times,
                                      const RunningIntegrand* integrand,
                                      IntegrationResult& result) {
  const int nq = controls.parameterCount();
  const bool quadrature = integrand != nullptr;
  if (!cvodes_ || !cvodes_->matches(nq, quadrature)) {
    cvodes_ = std::make_unique<CvodesSession>(options_, nq, quadrature);
  }
  if (!cvodes_->ok()) {
    result.status = IntegrationStatus::kSolverFailure;
    result.message = "CVODES could not be set up";
    cvodes_.reset();
    return;
  }
  cvodes_->run(kinematics_, workspace_, initial, controls, integrand, duration, sample_times,
               result);
}

}  // namespace terratraj::models
