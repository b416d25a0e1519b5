#pragma once
// ContinuousCurvatureSteering: the steering law of 001_... IV.C, after Scheuer & Fraichard
// (continuous-curvature paths) extended to an arbitrary initial curvature: turn toward the
// target as fast as the limits allow, then drive straight. Along arc length s the curvature
// follows a clothoid (|dkappa/ds| = sharpness) toward the turn curvature, an optional arc at
// that curvature, an anti-clothoid back to 0, and a line.
//
// The law is written in feedback form, one step of arc length at a time, so that it can run on
// the tangent-plane patches of the terrain (the target bearing is re-measured after every
// patch): given the heading error e to the target, the next curvature is the largest one (in
// the turn's direction) from which ramping back to 0 at the sharpness gains no more than the
// remaining heading error. In the plane this is exactly the clothoid / arc / anti-clothoid /
// line sequence (the switch to the anti-clothoid happens when kappa^2 / (2 sharpness) reaches
// the remaining error); the discrete form has no chattering on the line.
//
// The turn is shaped for a turn speed v_turn: sharpness = sigma_max / v_turn (so that
// |dkappa/dt| = |dkappa/ds| v <= sigma_max up to v_turn) and turn curvature
// min(kappa_max, omega_max / v_turn). The speed profile (SpeedProfile) then caps the speed
// wherever the path needs it.

#include "terratraj/models/vehicle_limits.hpp"

namespace terratraj::search {

/// The shape of one turn.
struct TurnShape {
  double sharpness = 1.0;       ///< |dkappa/ds| on the clothoids [1/m^2], > 0
  double turn_curvature = 1.0;  ///< |kappa| on the arc [1/m], > 0
  double turn_speed = 1.0;      ///< speed the turn was shaped for [m/s]
};

/// Lowest turn speed, as a fraction of v_max, that turnShape() uses (bounds the sharpness).
inline constexpr double kMinTurnSpeedFraction = 0.1;

/// Heading errors [rad] at most this large, with a curvature one step can bring to 0, count as
/// "on the line": nextCurvature() returns 0.
inline constexpr double kLineCaptureHeading = 1e-3;

/// The clothoid / arc / anti-clothoid / line steering law. Immutable; cheap to copy.
class ContinuousCurvatureSteering {
 public:
  /// Uses kappa_max [1/m], sigma_max [1/(m s)], omega_max [rad/s] and v_max [m/s] (all > 0).
  explicit ContinuousCurvatureSteering(const models::VehicleLimits& limits) : limits_(limits) {}

  /// The turn for a vehicle at speed `v_start` [m/s] with curvature `kappa_start` [1/m] that
  /// prefers to turn at `v_preferred` [m/s]. The turn speed is v_preferred clamped to
  /// [max(v_start, 0.1 v_max), min(v_max, omega_max / |kappa_start|)], so the start state
  /// already satisfies the turn's curvature and curvature-rate limits; when that range is empty
  /// (a start state beyond omega_max) its upper end is used.
  TurnShape turnShape(double v_start, double kappa_start, double v_preferred) const;

  /// The curvature [1/m] at the end of the next step of arc length `ds` [m] (> 0), starting
  /// from curvature `kappa` with heading error `heading_error` [rad] (target bearing minus
  /// heading, wrapped to (-pi, pi]). The curvature varies linearly over the step, by at most
  /// sharpness * ds, and stays within +-turn_curvature (or moves toward that range when it
  /// starts outside).
  double nextCurvature(double kappa, double heading_error, double ds, const TurnShape& turn) const;

  /// The curvature [1/m] after a step of `ds` [m] that only straightens: |kappa| decreases by
  /// at most sharpness * ds, never past 0 (the final approach, where the bearing to a target
  /// that is almost reached says nothing useful).
  static double straighten(double kappa, double ds, const TurnShape& turn);

  /// Heading gained [rad, signed like kappa] while the curvature ramps from `kappa` to 0 at
  /// `sharpness` (the anti-clothoid): kappa |kappa| / (2 sharpness).
  static double rampDownHeading(double kappa, double sharpness);

  /// The limits the law was built with.
  const models::VehicleLimits& limits() const { return limits_; }

 private:
  models::VehicleLimits limits_;
};

}  // namespace terratraj::search
