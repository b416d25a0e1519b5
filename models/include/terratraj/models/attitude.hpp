#pragma once
// Attitude of a vehicle resting on the terrain at a planar pose, and its derivatives.
//
// Conventions (docs/conventions.md): heading 0 along +x, counter-clockwise; pitch > 0 nose up;
// roll > 0 left side higher; z is the height of the vehicle's reference point [m].

#include <Eigen/Core>

namespace terratraj::models {

/// A planar pose in the local map frame: position [m] and heading [rad].
struct PlanarPose {
  double x = 0.0;
  double y = 0.0;
  double heading = 0.0;
};

/// Height of the vehicle's reference point [m], roll and pitch [rad].
struct Attitude {
  double z = 0.0;
  double roll = 0.0;
  double pitch = 0.0;
};

/// Outcome of an attitude computation. Never an exception: models are called inside
/// integrator and optimiser callbacks.
enum class AttitudeStatus {
  kOk,         ///< attitude and Jacobian are valid
  kNoTerrain,  ///< a contact point is off the map or over no data
  kNoContact,  ///< the suspension cannot rest on the terrain there (e.g. a cliff): no solution
};

/// Text for an AttitudeStatus ("ok", "no_terrain", "no_contact").
const char* attitudeStatusName(AttitudeStatus status);

/// The result of a terrain-following model at one pose.
struct AttitudeResult {
  Attitude attitude;
  /// d(z, roll, pitch) / d(x, y, heading): rows z, roll, pitch; columns x, y, heading.
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  /// Suspension configuration (rocker-bogie: rho, beta1, beta2 [rad]); zero for rigid models.
  Eigen::Vector3d suspension = Eigen::Vector3d::Zero();
  /// Largest |contact height error| of a wheel at the solution [m] (0 for closed-form models).
  double contact_residual = 0.0;
  /// Newton iterations used (0 for closed-form models).
  int iterations = 0;
};

}  // namespace terratraj::models
