#pragma once
// RoverIntegrator: integrates the rover kinematics under a ControlProfile, optionally with the
// forward sensitivities of the state with respect to the control parameters.
//
// Methods:
//  - kCvodes: SUNDIALS CVODES (Adams-Moulton, fixed-point corrector: the kinematics are not
//    stiff), relative / absolute tolerances, forward sensitivities (CVodeSensInit, simultaneous
//    corrector, optional error control on the sensitivities), dense output at the sample
//    times. The
//    CVODES memory is created once per integrator and re-initialised for each call.
//  - kRk4: classical fixed-step Runge-Kutta; sensitivities are the exact derivatives of the
//    discrete map (forward mode through the four stages).
//  - kEuler: the paper's explicit Euler (004_... eq. 14), the faithful baseline; sensitivities
//    likewise exact for the discrete map.
// Fixed-step methods use n = ceil(duration / step) equal steps.
// Failures (off the map, no contact, CVODES errors) are statuses, never exceptions; after one,
// final_state holds the last good state and t_reached its time.

#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/control_profile.hpp"
#include "terratraj/models/rover_kinematics.hpp"
#include "terratraj/models/trajectory.hpp"

namespace terratraj::models {

/// Which scheme integrates the kinematics.
enum class IntegrationMethod { kEuler, kRk4, kCvodes };

/// The name of a method ("euler", "rk4", "cvodes").
const char* integrationMethodName(IntegrationMethod method);

/// How to integrate.
struct IntegratorOptions {
  IntegrationMethod method = IntegrationMethod::kCvodes;
  double step = 0.01;                 ///< fixed-step methods [s], > 0
  double relative_tolerance = 1e-8;   ///< CVODES, > 0
  double absolute_tolerance = 1e-10;  ///< CVODES [m, rad], > 0
  long max_steps = 1000000;           ///< CVODES internal steps per call, > 0
  /// Wall clock by which an integration stops (kSolverFailure, "time limit"), checked every 64
  /// steps (CVODES's internal steps, or the fixed steps); absent: none. A solve's time limit,
  /// so that one stiff or very long integration (up to max_steps steps, or a final time of
  /// hours at a fixed step: seconds) cannot run past it.
  std::optional<std::chrono::steady_clock::time_point> deadline;
  bool sensitivities = false;  ///< also integrate d state / d q
  /// CVODES: include the sensitivities in the local error test. Off by default: the steps
  /// chosen for the state already give sensitivities that match finite differences to 1e-5
  /// (tests), and error control costs 6-20x more steps (docs/benchmarks.md).
  bool sensitivity_error_control = false;
};

/// How an integration ended.
enum class IntegrationStatus {
  kOk,
  kNoTerrain,      ///< the vehicle left the map or reached no-data cells
  kNoContact,      ///< the suspension could not rest on the terrain
  kSolverFailure,  ///< CVODES reported an error (message says which)
  kInvalidInput,   ///< bad options, duration or sample times (message says which)
};

/// The name of a status ("ok", "no_terrain", ...).
const char* integrationStatusName(IntegrationStatus status);

/// A scalar running integrand L(t, state, v, omega) integrated along with the state (a running
/// cost, a slope dwell): the integrator reports its integral and, with sensitivities, the
/// integral's derivative by q. Implementations must not allocate or throw (they run inside
/// CVODES callbacks).
class RunningIntegrand {
 public:
  virtual ~RunningIntegrand() = default;
  /// L at time t [s] given the kinematics' rates at the state (their attitude and its Jacobian
  /// included) and the inputs v [m/s], omega [rad/s]. When not null, d_state receives
  /// dL / d(x, y, heading) and d_input dL / d(v, omega).
  virtual double evaluate(double t, const RoverRates& rates, double v, double omega,
                          Eigen::Vector3d* d_state, Eigen::Vector2d* d_input) const = 0;
};

/// What an integration produced.
struct IntegrationResult {
  IntegrationStatus status = IntegrationStatus::kOk;
  std::string message;                                    ///< empty when status is kOk
  double t_reached = 0.0;                                 ///< [s]
  Eigen::Vector3d final_state = Eigen::Vector3d::Zero();  ///< (x, y, heading) at t_reached
  Eigen::MatrixXd sensitivity;                            ///< 3 x parameterCount(), if requested
  Trajectory samples;                                     ///< the states at the sample times
  /// With sensitivities and samples: d(x, y, heading) / dq at sample i in rows 3i..3i+2.
  Eigen::MatrixXd sample_sensitivity;
  double integral = 0.0;  ///< integral of the running integrand over [0, t_reached], if given
  Eigen::RowVectorXd integral_sensitivity;  ///< d integral / dq, with sensitivities
  long steps = 0;                           ///< steps taken
  long rhs_evaluations = 0;                 ///< kinematics evaluations
};

/// Integrates rover kinematics. Not thread-safe: use one per thread.
class RoverIntegrator {
 public:
  /// Throws std::invalid_argument for invalid options. The kinematics' model must outlive it.
  RoverIntegrator(const RoverKinematics& kinematics, const IntegratorOptions& options);
  ~RoverIntegrator();
  RoverIntegrator(const RoverIntegrator&) = delete;
  RoverIntegrator& operator=(const RoverIntegrator&) = delete;

  const IntegratorOptions& options() const { return options_; }

  /// Integrates from `initial` (x, y, heading) at t = 0 to `duration` [s] under `controls`.
  /// `sample_times` (ascending, within [0, duration]) selects the rows of result.samples; empty
  /// gives no samples. `integrand`, when not null, is integrated alongside (result.integral).
  /// Reuses `result`'s storage.
  void integrate(const Eigen::Vector3d& initial, const ControlProfile& controls, double duration,
                 const std::vector<double>& sample_times, IntegrationResult& result,
                 const RunningIntegrand* integrand = nullptr);

 private:
  class CvodesSession;
  void integrateCvodes(const Eigen::Vector3d& initial, const ControlProfile& controls,
                       double duration, const std::vector<double>& sample_times,
                       const RunningIntegrand* integrand, IntegrationResult& result);
  void integrateFixedStep(const Eigen::Vector3d& initial, const ControlProfile& controls,
                          double duration, const std::vector<double>& sample_times,
                          const RunningIntegrand* integrand, IntegrationResult& result);

  RoverKinematics kinematics_;
  IntegratorOptions options_;
  AttitudeWorkspace workspace_;
  std::unique_ptr<CvodesSession> cvodes_;
};

/// Uniform sample times 0, dt, 2 dt, ..., duration (duration always included).
std::vector<double> uniformSampleTimes(double duration, double dt);

}  // namespace terratraj::models
