#pragma once
// ParametricTrajectoryModel: a boundary-value problem as functions of the control unknowns q
// (004_... 2.2): the terminal error c(q) = P(q) - P_f in (x, y, heading) (eq. 3), the cost
// J(q), and their derivatives, by forward sensitivities or by finite differences (eqs. 10-11).
//
// Problem vs data (Crocoddyl style): the model holds the problem and its integrators (one
// with sensitivities, one without; not thread-safe: one model per thread); everything an
// evaluation produces lives in a ParametricEvaluation owned by the caller.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "terratraj/models/rover_integrator.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/parametric_controls.hpp"
#include "terratraj/ocp/path_constraints.hpp"
#include "terratraj/ocp/slope_dwell_integrand.hpp"

namespace terratraj::ocp {

/// How derivatives are computed.
enum class DerivativeMode {
  kNone,              ///< values only
  kSensitivity,       ///< CVODES / discrete forward sensitivities (one integration)
  kFiniteDifference,  ///< forward differences, 004_... eq. 10 (n + 1 integrations)
};

/// Settings of the model.
struct ParametricModelOptions {
  models::IntegratorOptions integrator;  ///< `sensitivities` is set by the model as needed
  double finite_difference_step = 1e-6;  ///< eq. 10's e, on every q_k
};

/// Everything one evaluation produces.
struct ParametricEvaluation {
  models::IntegrationStatus status = models::IntegrationStatus::kOk;
  std::string message;                                       ///< why, when status is not kOk
  Eigen::Vector3d terminal_state = Eigen::Vector3d::Zero();  ///< (x, y, heading) at t_f
  Eigen::Vector3d terminal_error = Eigen::Vector3d::Zero();  ///< c(q); heading wrapped
  double cost = 0.0;                                         ///< J(q) [s]
  double running_cost = 0.0;              ///< integral of alpha (roll^2 + pitch^2) dt, 0 for kTime
  Eigen::MatrixXd jacobian;               ///< 3 x n: dc / dq (with derivatives)
  Eigen::VectorXd gradient;               ///< n: dJ / dq (with derivatives)
  models::IntegrationResult integration;  ///< storage for the integrator

  bool ok() const { return status == models::IntegrationStatus::kOk; }
};

/// Points along the trajectory at fixed fractions tau of t_f, with their derivatives by q (for
/// path constraints).
struct PathEvaluation {
  std::vector<PathPoint> points;
  /// d (x, y, heading, v, omega, v', omega') / dq at each point (kPathVariables x n).
  std::vector<Eigen::Matrix<double, kPathVariables, Eigen::Dynamic>> derivatives;
};

/// The boundary-value problem as a function of q on one terrain-following model.
class ParametricTrajectoryModel {
 public:
  /// The vehicle model must outlive this object. Throws std::invalid_argument for invalid
  /// integrator options.
  ParametricTrajectoryModel(const models::TerrainFollowingModel& vehicle,
                            const BoundaryValueProblem& problem,
                            const ParametricModelOptions& options = {});

  const BoundaryValueProblem& problem() const { return problem_; }
  const ParametricModelOptions& options() const { return options_; }
  const models::TerrainFollowingModel& vehicle() const { return *vehicle_; }
  int parameterCount() const { return controls_.parameterCount(); }
  int finalTimeIndex() const { return controls_.finalTimeIndex(); }
  /// The controls at the q of the last evaluation.
  const ParametricControls& controls() const { return controls_; }

  /// Evaluates c, J (and their derivatives per `mode`) at q. Returns out.ok(); on failure
  /// (off the map, no contact, t_f <= 0, NaN in q) out.status / message say why. Never throws.
  bool evaluate(const Eigen::VectorXd& q, DerivativeMode mode, ParametricEvaluation& out);

  /// As evaluate() with kNone or kSensitivity, and also the points at the fractions `tau`
  /// (ascending, in [0, 1]) of t_f, from the same integration.
  bool evaluateWithPath(const Eigen::VectorXd& q, bool derivatives, const std::vector<double>& tau,
                        ParametricEvaluation& out, PathEvaluation& path);

  /// Hessian of the Lagrangian J + lambda' c at q by finite differences with step h:
  /// of sensitivity gradients (kSensitivity: n integrations) or of values (kFiniteDifference,
  /// eq. 11: n (n + 3) / 2 integrations). Symmetric. False if an integration fails.
  bool lagrangianHessian(const Eigen::VectorXd& q, const Eigen::Vector3d& lambda,
                         DerivativeMode mode, double h, Eigen::MatrixXd& hessian);

  /// Integrations run so far (each trajectory integration counts one).
  long integrations() const { return integrations_; }

 private:
  bool integrate(const Eigen::VectorXd& q, bool sensitivities, ParametricEvaluation& out,
                 const std::vector<double>& sample_times);
  bool finiteDifferences(const Eigen::VectorXd& q, ParametricEvaluation& out);

  const models::TerrainFollowingModel* vehicle_;
  BoundaryValueProblem problem_;
  ParametricModelOptions options_;
  models::RoverKinematics kinematics_;
  models::RoverIntegrator plain_;
  models::RoverIntegrator with_sensitivities_;
  ParametricControls controls_;
  SlopeDwellIntegrand slope_dwell_;
  models::AttitudeWorkspace terminal_workspace_;
  models::RoverRates terminal_rates_;
  ParametricEvaluation scratch_, scratch2_;
  Eigen::VectorXd dv_dq_, domega_dq_, dv_dot_dq_, domega_dot_dq_;
  std::vector<double> sample_times_;
  long integrations_ = 0;
};

}  // namespace terratraj::ocp
