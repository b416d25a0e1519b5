#include "shooting_interval.hpp"

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <array>
#include <cstdio>
#include <vector>

namespace terratraj::ocp::detail {
namespace {

// What the C callbacks need. Nothing here throws.
struct CallbackData {
  const TranscriptionModel* model = nullptr;
  models::AttitudeWorkspace workspace;
  bool linear = false;
  Eigen::Vector2d u0 = Eigen::Vector2d::Zero(), u1 = Eigen::Vector2d::Zero();
  double duration = 0.0;  // H = t_f delta
  double delta = 0.0;
  models::RoverStateSpaceRates rates;
  bool cached = false;
  double cached_s = 0.0;
  StateVector cached_z = StateVector::Zero();
  std::array<char, 256> last_error{};
};

Eigen::Vector2d controlAt(const CallbackData& data, double s) {
  return data.linear ? Eigen::Vector2d(data.u0 + s * (data.u1 - data.u0)) : data.u0;
}

bool evaluate(CallbackData& data, double s, N_Vector y) {
  const Eigen::Map<const StateVector> z(N_VGetArrayPointer(y));
  if (data.cached && data.cached_s == s && data.cached_z == z) return true;
  if (data.model->kinematics().stateSpaceRates(z, controlAt(data, s), data.workspace, data.rates) !=
      models::AttitudeStatus::kOk) {
    data.cached = false;
    return false;
  }
  data.cached = true;
  data.cached_s = s;
  data.cached_z = z;
  return true;
}

int rhs(realtype s, N_Vector y, N_Vector ydot, void* user_data) {
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  if (!evaluate(data, s, y)) return -1;
  Eigen::Map<StateVector>(N_VGetArrayPointer(ydot)) = data.duration * data.rates.rate;
  return 0;
}

int sensitivityRhs(int ns, realtype s, N_Vector y, N_Vector /*ydot*/, N_Vector* ys,
                   N_Vector* ys_dot, void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/) {
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  if (!evaluate(data, s, y)) return -1;
  const double h = data.duration;
  for (int i = 0; i < ns; ++i) {
    const Eigen::Map<const StateVector> sens(N_VGetArrayPointer(ys[i]));
    Eigen::Map<StateVector> out(N_VGetArrayPointer(ys_dot[i]));
    out = h * (data.rates.d_state * sens);
    if (i >= kStateSize && i < kStateSize + kControlSize) {
      const double weight = data.linear ? 1.0 - s : 1.0;
      out += h * weight * data.rates.d_control.col(i - kStateSize);
    } else if (data.linear && i >= kStateSize + kControlSize && i < ns - 1) {
      out += h * s * data.rates.d_control.col(i - kStateSize - kControlSize);
    } else if (i == ns - 1) {
      out += data.delta * data.rates.rate;  // d H / d t_f = delta
    }
  }
  return 0;
}

void recordError(int error_code, const char* module, const char* function, char* message,
                 void* user_data) {
  if (error_code > 0) return;
  CallbackData& data = *static_cast<CallbackData*>(user_data);
  std::snprintf(data.last_error.data(), data.last_error.size(), "%s %s: %s", module, function,
                message);
}

}  // namespace

struct ShootingInterval::Session {
  SUNContext context = nullptr;
  void* memory = nullptr;
  N_Vector y = nullptr;
  N_Vector* ys = nullptr;
  SUNNonlinearSolver solver = nullptr, sensitivity_solver = nullptr;
  int parameters = 0;
  bool ok = false;
  bool sensitivities_on = false;
  CallbackData data;

  Session(const TranscriptionModel& model, bool linear, double rtol, double atol) {
    data.model = &model;
    data.linear = linear;
    parameters = kStateSize + kControlSize * (linear ? 2 : 1) + 1;
    ok = SUNContext_Create(nullptr, &context) == 0;
    if (!ok) return;
    y = N_VNew_Serial(kStateSize, context);
    memory = CVodeCreate(CV_ADAMS, context);
    ok = y != nullptr && memory != nullptr;
    if (!ok) return;
    N_VConst(0.0, y);
    ok = CVodeInit(memory, rhs, 0.0, y) == CV_SUCCESS &&
         CVodeSStolerances(memory, rtol, atol) == CV_SUCCESS &&
         CVodeSetUserData(memory, &data) == CV_SUCCESS &&
         CVodeSetErrHandlerFn(memory, recordError, &data) == CV_SUCCESS &&
         CVodeSetMaxNumSteps(memory, 100000) == CV_SUCCESS;
    if (!ok) return;
    solver = SUNNonlinSol_FixedPoint(y, 0, context);
    ok = solver != nullptr && CVodeSetNonlinearSolver(memory, solver) == CV_SUCCESS;
    if (!ok) return;
    ys = N_VCloneVectorArray(parameters, y);
    ok = ys != nullptr;
    if (!ok) return;
    for (int i = 0; i < parameters; ++i) N_VConst(0.0, ys[i]);
    std::vector<realtype> abs_tolerances(static_cast<std::size_t>(parameters), atol);
    ok = CVodeSensInit(memory, parameters, CV_SIMULTANEOUS, sensitivityRhs, ys) == CV_SUCCESS &&
         CVodeSensSStolerances(memory, rtol, abs_tolerances.data()) == CV_SUCCESS &&
         CVodeSetSensErrCon(memory, SUNFALSE) == CV_SUCCESS;
    if (!ok) return;
    sensitivity_solver = SUNNonlinSol_FixedPointSens(parameters + 1, y, 0, context);
    ok = sensitivity_solver != nullptr &&
         CVodeSetNonlinearSolverSensSim(memory, sensitivity_solver) == CV_SUCCESS;
    sensitivities_on = true;
  }
  ~Session() {
    if (ys != nullptr) N_VDestroyVectorArray(ys, parameters);
    if (memory != nullptr) CVodeFree(&memory);
    if (sensitivity_solver != nullptr) SUNNonlinSolFree(sensitivity_solver);
    if (solver != nullptr) SUNNonlinSolFree(solver);
    if (y != nullptr) N_VDestroy(y);
    if (context != nullptr) SUNContext_Free(&context);
  }
};

ShootingInterval::ShootingInterval(const TranscriptionModel& model, bool linear_controls,
                                   double relative_tolerance, double absolute_tolerance)
    : session_(std::make_unique<Session>(model, linear_controls, relative_tolerance,
                                         absolute_tolerance)) {}

ShootingInterval::~ShootingInterval() = default;

int ShootingInterval::parameterCount() const { return session_->parameters; }

bool ShootingInterval::integrate(const StateVector& start, const Eigen::Vector2d& u0,
                                 const Eigen::Vector2d& u1, double t_f, double delta,
                                 bool sensitivities, IntervalResult& result) {
  Session& s = *session_;
  if (!s.ok) {
    result.message = "CVODES could not be set up";
    return false;
  }
  CallbackData& data = s.data;
  data.u0 = u0;
  data.u1 = u1;
  data.delta = delta;
  data.duration = t_f * delta;
  data.cached = false;
  data.last_error[0] = '\0';
  Eigen::Map<StateVector>(N_VGetArrayPointer(s.y)) = start;
  if (CVodeReInit(s.memory, 0.0, s.y) != CV_SUCCESS ||
      CVodeSetStopTime(s.memory, 1.0) != CV_SUCCESS) {
    result.message = "CVODES re-initialisation failed";
    return false;
  }
  if (sensitivities) {
    for (int i = 0; i < s.parameters; ++i) {
      N_VConst(0.0, s.ys[i]);
      if (i < kStateSize) N_VGetArrayPointer(s.ys[i])[i] = 1.0;
    }
    if (CVodeSensReInit(s.memory, CV_SIMULTANEOUS, s.ys) != CV_SUCCESS) {
      result.message = "CVODES sensitivity re-initialisation failed";
      return false;
    }
  } else if (CVodeSensToggleOff(s.memory) != CV_SUCCESS) {
    result.message = "CVODES could not switch sensitivities off";
    return false;
  }
  realtype reached = 0.0;
  const int flag = CVode(s.memory, 1.0, s.y, &reached, CV_NORMAL);
  if (flag < 0) {
    result.message = data.last_error[0] != '\0' ? std::string(data.last_error.data())
                                                : std::string("the vehicle left the terrain");
    return false;
  }
  result.end = Eigen::Map<const StateVector>(N_VGetArrayPointer(s.y));
  if (sensitivities) {
    if (CVodeGetSens(s.memory, &reached, s.ys) != CV_SUCCESS) {
      result.message = "CVODES sensitivities unavailable";
      return false;
    }
    result.sensitivity.resize(kStateSize, s.parameters);
    for (int i = 0; i < s.parameters; ++i) {
      result.sensitivity.col(i) = Eigen::Map<const StateVector>(N_VGetArrayPointer(s.ys[i]));
    }
  }
  return true;
}

}  // namespace terratraj::ocp::detail
