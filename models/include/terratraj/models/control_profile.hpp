#pragma once
// Control profiles: body speed v(t) and yaw rate omega(t) as functions of time and of a
// parameter vector q, with their derivatives by q (for sensitivities).

#include <Eigen/Core>
#include <vector>

namespace terratraj::models {

/// v(t; q) [m/s] and omega(t; q) [rad/s].
class ControlProfile {
 public:
  virtual ~ControlProfile() = default;
  /// Number of parameters q.
  virtual int parameterCount() const = 0;
  /// Evaluates the controls at t [s]. When dv_dq / domega_dq are not null they receive
  /// parameterCount() derivatives each. Must not allocate or throw (called inside CVODES).
  virtual void evaluate(double t, double& v, double& omega, double* dv_dq,
                        double* domega_dq) const = 0;
};

/// Polynomials in time: v(t) = sum_i a_i t^i, omega(t) = sum_j b_j t^j; q = (a_0.., b_0..).
class PolynomialControls final : public ControlProfile {
 public:
  /// Coefficients from order 0 up; either may be empty (a zero control).
  PolynomialControls(std::vector<double> speed_coefficients,
                     std::vector<double> yaw_rate_coefficients);

  int parameterCount() const override;
  void evaluate(double t, double& v, double& omega, double* dv_dq,
                double* domega_dq) const override;

  /// The parameters q in order (speed coefficients, then yaw-rate coefficients).
  Eigen::VectorXd parameters() const;
  /// Replaces the parameters; q must have parameterCount() entries.
  void setParameters(const Eigen::VectorXd& q);

 private:
  std::vector<double> speed_;
  std::vector<double> yaw_rate_;
};

}  // namespace terratraj::models
