#include "terratraj/models/control_profile.hpp"

#include <stdexcept>

namespace terratraj::models {
namespace {

// sum_i c_i t^i, and (when d is not null) d_i = t^i.
double polynomial(const std::vector<double>& coefficients, double t, double* d) {
  double value = 0.0, power = 1.0;
  for (std::size_t i = 0; i < coefficients.size(); ++i) {
    value += coefficients[i] * power;
    if (d != nullptr) d[i] = power;
    power *= t;
  }
  return value;
}

}  // namespace

PolynomialControls::PolynomialControls(std::vector<double> speed_coefficients,
                                       std::vector<double> yaw_rate_coefficients)
    : speed_(std::move(speed_coefficients)), yaw_rate_(std::move(yaw_rate_coefficients)) {}

int PolynomialControls::parameterCount() const {
  return static_cast<int>(speed_.size() + yaw_rate_.size());
}

void PolynomialControls::evaluate(double t, double& v, double& omega, double* dv_dq,
                                  double* domega_dq) const {
  const std::size_t n_speed = speed_.size();
  const std::size_t n_total = n_speed + yaw_rate_.size();
  if (dv_dq != nullptr) {
    for (std::size_t i = n_speed; i < n_total; ++i) dv_dq[i] = 0.0;
  }
  if (domega_dq != nullptr) {
    for (std::size_t i = 0; i < n_speed; ++i) domega_dq[i] = 0.0;
  }
  v = polynomial(speed_, t, dv_dq);
  omega = polynomial(yaw_rate_, t, domega_dq == nullptr ? nullptr : domega_dq + n_speed);
}

Eigen::VectorXd PolynomialControls::parameters() const {
  Eigen::VectorXd q(parameterCount());
  for (std::size_t i = 0; i < speed_.size(); ++i) q(static_cast<Eigen::Index>(i)) = speed_[i];
  for (std::size_t j = 0; j < yaw_rate_.size(); ++j) {
    q(static_cast<Eigen::Index>(speed_.size() + j)) = yaw_rate_[j];
  }
  return q;
}

void PolynomialControls::setParameters(const Eigen::VectorXd& q) {
  if (q.size() != parameterCount()) {
    throw std::invalid_argument("PolynomialControls::setParameters: wrong parameter count");
  }
  for (std::size_t i = 0; i < speed_.size(); ++i) speed_[i] = q(static_cast<Eigen::Index>(i));
  for (std::size_t j = 0; j < yaw_rate_.size(); ++j) {
    yaw_rate_[j] = q(static_cast<Eigen::Index>(speed_.size() + j));
  }
}

}  // namespace terratraj::models
