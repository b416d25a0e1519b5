#pragma once
// ParametricControls: the polynomial controls of 004_... eqs. 12-13 in normalised time.
//
// With tau = t / t_f in [0, 1]:
//   omega(t) = omega_0 + sum_{k=1..K} w_k tau^k,   w_K = (omega_f - omega_0) - sum_{k<K} w_k
//   v(t)     = v_0     + sum_{k=1..M} s_k tau^k,   s_M = (v_f - v_0) - sum_{k<M} s_k
// so the terminal yaw rate and speed hold in closed form for every q (eq. 13), and the unknowns
// are q = (w_1..w_{K-1}, s_1..s_{M-1}, t_f). These are the paper's (b1, c1, d1, t_f) scaled by
// powers of t_f (w_k = b_k t_f^k), which keeps the Jacobian well conditioned as t_f changes.
// Derivatives by q are at fixed t (what forward sensitivities need), t_f included.

#include <Eigen/Core>

#include "terratraj/models/control_profile.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::ocp {

/// Control rates (v', omega') [m/s^2, rad/s^2] at one time.
struct ControlRates {
  double v_dot = 0.0;
  double omega_dot = 0.0;
};

/// Speed and yaw-rate polynomials with closed-form terminal values. Not thread-safe to mutate;
/// evaluate() is const and allocation-free.
class ParametricControls final : public models::ControlProfile {
 public:
  /// Controls from `start` to `goal` values of v and omega with the given orders (each >= 1).
  ParametricControls(const VehicleState& start, const VehicleState& goal,
                     const ControlOrders& orders);

  /// Number of unknowns: (K - 1) + (M - 1) + 1.
  int parameterCount() const override { return yaw_free_ + speed_free_ + 1; }
  /// Index of t_f in q (the last).
  int finalTimeIndex() const { return yaw_free_ + speed_free_; }
  /// Index of the first free speed coefficient in q.
  int speedIndex() const { return yaw_free_; }

  void evaluate(double t, double& v, double& omega, double* dv_dq,
                double* domega_dq) const override;

  /// v' and omega' at t [s]; when not null, d_v_dot / d_omega_dot receive parameterCount()
  /// derivatives by q each.
  ControlRates rates(double t, double* d_v_dot, double* d_omega_dot) const;

  /// The unknowns q. t_f = q(finalTimeIndex()) [s].
  const Eigen::VectorXd& parameters() const { return q_; }
  double finalTime() const { return q_(finalTimeIndex()); }
  /// Replaces q (size parameterCount(); t_f > 0 expected by callers, not checked).
  void setParameters(const Eigen::VectorXd& q) { q_ = q; }

  /// Full coefficient lists (w_1..w_K) and (s_1..s_M) for reports.
  Eigen::VectorXd yawRateCoefficients() const;
  Eigen::VectorXd speedCoefficients() const;

 private:
  double start_v_, start_omega_, delta_v_, delta_omega_;
  int yaw_order_, speed_order_, yaw_free_, speed_free_;
  Eigen::VectorXd q_;
};

}  // namespace terratraj::ocp
