#pragma once
// Terrain-following rover kinematics (004_... eq. 2, the integrand of eq. 14).
//
// Reduced form: state s = (x, y, heading) [m, m, rad], inputs body speed v [m/s] and yaw rate
// omega [rad/s]:
//   x' = v cos(heading) cos(pitch),  y' = v sin(heading) cos(pitch),
//   heading' = omega cos(roll) / cos(pitch),
// with roll and pitch from a TerrainFollowingModel at (x, y, heading).
// State-space form (for transcription and the planners): state (x, y, heading, v, omega),
// controls (v', omega') [m/s^2, rad/s^2]: the same three rates plus v' and omega'.
// Both give analytic derivatives, checked against finite differences in the tests.

#include <Eigen/Core>

#include "terratraj/models/attitude.hpp"
#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::models {

/// Rates of the reduced state and their derivatives.
struct RoverRates {
  Eigen::Vector3d rate = Eigen::Vector3d::Zero();     ///< (x', y', heading')
  Eigen::Matrix3d d_state = Eigen::Matrix3d::Zero();  ///< d rate / d (x, y, heading)
  Eigen::Matrix<double, 3, 2> d_input =
      Eigen::Matrix<double, 3, 2>::Zero();  ///< d rate / d (v, omega)
  AttitudeResult attitude;                  ///< attitude at the state
};

/// Rates of the state-space form and their derivatives.
struct RoverStateSpaceRates {
  Eigen::Matrix<double, 5, 1> rate = Eigen::Matrix<double, 5, 1>::Zero();
  Eigen::Matrix<double, 5, 5> d_state = Eigen::Matrix<double, 5, 5>::Zero();
  Eigen::Matrix<double, 5, 2> d_control = Eigen::Matrix<double, 5, 2>::Zero();
  AttitudeResult attitude;
};

/// The rover's motion on the terrain. Immutable; the workspace carries the attitude warm start.
class RoverKinematics {
 public:
  /// The model must outlive this object.
  explicit RoverKinematics(const TerrainFollowingModel& model) : model_(&model) {}

  const TerrainFollowingModel& model() const { return *model_; }

  /// Reduced form at state (x, y, heading) with inputs (v, omega). Status other than kOk when
  /// the attitude cannot be computed (off the map, no data, no contact); never throws.
  AttitudeStatus rates(const Eigen::Vector3d& state, double v, double omega,
                       AttitudeWorkspace& workspace, RoverRates& out) const;

  /// State-space form at state (x, y, heading, v, omega) with controls (v', omega').
  AttitudeStatus stateSpaceRates(const Eigen::Matrix<double, 5, 1>& state,
                                 const Eigen::Vector2d& control, AttitudeWorkspace& workspace,
                                 RoverStateSpaceRates& out) const;

 private:
  const TerrainFollowingModel* model_;
};

}  // namespace terratraj::models
