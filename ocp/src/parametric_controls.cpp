#include "terratraj/ocp/parametric_controls.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {
namespace {

// A polynomial's value minus p0 and its first and second derivatives by tau.
struct PolynomialSample {
  double value = 0.0, slope = 0.0, curve = 0.0;
};

// One closed polynomial p(tau) = p0 + sum_{k=1..K} c_k tau^k, c_K = delta - sum_{k<K} c_k,
// with free coefficients c_1..c_{K-1} = free[0..K-2].
struct ClosedPolynomial {
  const double* free;
  int order;
  double delta;

  double top() const {
    double c = delta;
    for (int k = 1; k < order; ++k) c -= free[k - 1];
    return c;
  }
  PolynomialSample evaluate(double tau) const {
    PolynomialSample out;
    const double c_top = top();
    double power = 1.0;   // tau^(k-1)
    double power2 = 0.0;  // tau^(k-2)
    for (int k = 1; k <= order; ++k) {
      const double c = k < order ? free[k - 1] : c_top;
      out.curve += k * (k - 1) * c * power2;
      out.slope += k * c * power;
      out.value += c * power * tau;
      power2 = power;
      power *= tau;
    }
    return out;
  }
  // All coefficients c_1..c_K.
  Eigen::VectorXd coefficients() const {
    Eigen::VectorXd c(order);
    for (int k = 1; k < order; ++k) c(k - 1) = free[k - 1];
    c(order - 1) = top();
    return c;
  }
  // d value / d c_k = tau^k - tau^K; d (d value / d tau) / d c_k = k tau^(k-1) - K tau^(K-1).
  void freeDerivatives(double tau, double* d_value, double* d_slope) const {
    const double top = std::pow(tau, order);
    const double top_slope = order * std::pow(tau, order - 1);
    double power = 1.0;  // tau^(k-1)
    for (int k = 1; k < order; ++k) {
      if (d_value != nullptr) d_value[k - 1] = power * tau - top;
      if (d_slope != nullptr) d_slope[k - 1] = k * power - top_slope;
      power *= tau;
    }
  }
};

}  // namespace

ParametricControls::ParametricControls(const VehicleState& start, const VehicleState& goal,
                                       const ControlOrders& orders)
    : start_v_(start.v),
      start_omega_(start.omega),
      delta_v_(goal.v - start.v),
      delta_omega_(goal.omega - start.omega),
      yaw_order_(std::max(1, orders.yaw_rate)),
      speed_order_(std::max(1, orders.speed)),
      yaw_free_(yaw_order_ - 1),
      speed_free_(speed_order_ - 1),
      q_(Eigen::VectorXd::Zero(yaw_free_ + speed_free_ + 1)) {
  q_(finalTimeIndex()) = 1.0;
}

void ParametricControls::evaluate(double t, double& v, double& omega, double* dv_dq,
                                  double* domega_dq) const {
  const double tf = finalTime();
  const double tau = t / tf;
  const ClosedPolynomial yaw{q_.data(), yaw_order_, delta_omega_};
  const ClosedPolynomial speed{q_.data() + yaw_free_, speed_order_, delta_v_};
  const PolynomialSample w = yaw.evaluate(tau), s = speed.evaluate(tau);
  omega = start_omega_ + w.value;
  v = start_v_ + s.value;
  if (dv_dq == nullptr && domega_dq == nullptr) return;
  const int n = parameterCount();
  const int itf = finalTimeIndex();
  // At fixed t, d tau / d t_f = -tau / t_f.
  if (domega_dq != nullptr) {
    std::fill(domega_dq, domega_dq + n, 0.0);
    yaw.freeDerivatives(tau, domega_dq, nullptr);
    domega_dq[itf] = -w.slope * tau / tf;
  }
  if (dv_dq != nullptr) {
    std::fill(dv_dq, dv_dq + n, 0.0);
    speed.freeDerivatives(tau, dv_dq + yaw_free_, nullptr);
    dv_dq[itf] = -s.slope * tau / tf;
  }
}

ControlRates ParametricControls::rates(double t, double* d_v_dot, double* d_omega_dot) const {
  const double tf = finalTime();
  const double tau = t / tf;
  const ClosedPolynomial yaw{q_.data(), yaw_order_, delta_omega_};
  const ClosedPolynomial speed{q_.data() + yaw_free_, speed_order_, delta_v_};
  const PolynomialSample w = yaw.evaluate(tau), s = speed.evaluate(tau);
  const ControlRates out{s.slope / tf, w.slope / tf};
  const int n = parameterCount();
  const int itf = finalTimeIndex();
  // rate = p'(tau) / t_f; d/dt_f at fixed t = -p'/t_f^2 - p'' tau / t_f^2.
  if (d_omega_dot != nullptr) {
    std::fill(d_omega_dot, d_omega_dot + n, 0.0);
    yaw.freeDerivatives(tau, nullptr, d_omega_dot);
    for (int k = 0; k < yaw_free_; ++k) d_omega_dot[k] /= tf;
    d_omega_dot[itf] = -(w.slope + w.curve * tau) / (tf * tf);
  }
  if (d_v_dot != nullptr) {
    std::fill(d_v_dot, d_v_dot + n, 0.0);
    speed.freeDerivatives(tau, nullptr, d_v_dot + yaw_free_);
    for (int k = 0; k < speed_free_; ++k) d_v_dot[yaw_free_ + k] /= tf;
    d_v_dot[itf] = -(s.slope + s.curve * tau) / (tf * tf);
  }
  return out;
}

Eigen::VectorXd ParametricControls::yawRateCoefficients() const {
  return ClosedPolynomial{q_.data(), yaw_order_, delta_omega_}.coefficients();
}

Eigen::VectorXd ParametricControls::speedCoefficients() const {
  return ClosedPolynomial{q_.data() + yaw_free_, speed_order_, delta_v_}.coefficients();
}

}  // namespace terratraj::ocp
