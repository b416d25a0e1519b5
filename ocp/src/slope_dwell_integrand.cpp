#include "terratraj/ocp/slope_dwell_integrand.hpp"

namespace terratraj::ocp {

double SlopeDwellIntegrand::evaluate(double /*t*/, const models::RoverRates& rates, double /*v*/,
                                     double /*omega*/, Eigen::Vector3d* d_state,
                                     Eigen::Vector2d* d_input) const {
  const models::AttitudeResult& a = rates.attitude;
  const double roll = a.attitude.roll;
  const double pitch = a.attitude.pitch;
  if (d_state != nullptr) {
    // Jacobian rows: z, roll, pitch.
    *d_state = 2.0 * alpha_ * (roll * a.jacobian.row(1) + pitch * a.jacobian.row(2)).transpose();
  }
  if (d_input != nullptr) d_input->setZero();
  return alpha_ * (roll * roll + pitch * pitch);
}

}  // namespace terratraj::ocp
