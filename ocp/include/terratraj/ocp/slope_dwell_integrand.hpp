#pragma once
// SlopeDwellIntegrand: the slope-dwell part of 004_... eq. 17, alpha (roll^2 + pitch^2).

#include "terratraj/models/rover_integrator.hpp"

namespace terratraj::ocp {

/// L = alpha (roll^2 + pitch^2) [1/rad^2 * rad^2]; its state derivative comes from the
/// attitude Jacobian of the terrain-following model.
class SlopeDwellIntegrand final : public models::RunningIntegrand {
 public:
  explicit SlopeDwellIntegrand(double alpha) : alpha_(alpha) {}
  double evaluate(double t, const models::RoverRates& rates, double v, double omega,
                  Eigen::Vector3d* d_state, Eigen::Vector2d* d_input) const override;

 private:
  double alpha_;
};

}  // namespace terratraj::ocp
