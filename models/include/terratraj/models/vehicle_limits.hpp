#pragma once
// VehicleLimits: the bounds a trajectory must respect (the problem file's `vehicle.limits`).

namespace terratraj::models {

/// Degrees -> radians factor.
inline constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

/// Bounds on speed, acceleration, turning and attitude. All > 0 (the problem loader checks).
struct VehicleLimits {
  double v_max = 1.0;                           ///< speed [m/s]
  double a_max = 0.5;                           ///< |acceleration| [m/s^2]
  double omega_max = 1.0;                       ///< |yaw rate| [rad/s]
  double kappa_max = 1.0;                       ///< |curvature| [1/m]
  double sigma_max = 0.5;                       ///< |curvature rate| d(kappa)/dt [1/(m s)]
  double pitch_max = 17.0 * kRadiansPerDegree;  ///< |pitch| [rad], in (0, pi/2)
  double roll_max = 20.0 * kRadiansPerDegree;   ///< |roll| [rad], in (0, pi/2)
};

}  // namespace terratraj::models
