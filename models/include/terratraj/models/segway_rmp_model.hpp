#pragma once
// SegwayRmpModel: the point model of the Segway RMP on tangent-plane patches, with its
// constraints (001_... III.B-D).
//
// State (x, y, heading, v, omega) in the map frame plus the platform pitch, which is not
// integrated but read from the pitch response (acceleration, slope). Controls (v', omega').
// Over a patch the robot moves in the patch's plane: x' = v cos(psi), y' = v sin(psi),
// psi' = omega, v' = u1, omega' = u2 (the extracted equation lost the psi' row; it is omega).
// Constraints, each reported as a violation in its own units (0 = satisfied):
//  (1) |curvature| <= kappa_max(v), i.e. |omega| <= v kappa_max(v), with
//      kappa_max(v) = min(kappa_max, a_lat_max / v^2) (the RMP turns in place; at speed its
//      turning rate is limited); |d curvature / dt| <= sigma_max, i.e.
//      |omega' - v' kappa| <= v sigma_max;
//  (2) the non-holonomic constraint: holds by construction of the motion;
//  (3) |pitch| <= pitch_max (the platform pitch from the look-up);
//  (4) |roll| <= roll_max (the patch's roll);
//  (5) 0 <= v <= min(v_max, v_max(slope)); slopes steeper than max_slope are not traversable;
//  (6) |v'| <= min(a_max, a_max(slope)).

#include <Eigen/Core>
#include <optional>

#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/terrain/tangent_plane_patch.hpp"

namespace terratraj::models {

/// Limits of the RMP beyond its look-ups. Defaults from 001_...: 3.5 m/s, 2 m/s^2, 17 deg.
struct SegwayLimits {
  double v_max = 3.5;                 ///< [m/s]
  double a_max = 2.0;                 ///< [m/s^2]
  double kappa_max = 4.0;             ///< [1/m] curvature cap at low speed
  double lateral_acceleration = 2.0;  ///< [m/s^2] kappa_max(v) = min(kappa_max, this / v^2)
  double sigma_max = 2.0;             ///< [1/(m s)] curvature rate
  double pitch_max = 0.698;           ///< [rad] platform pitch (40 deg: the RMP falls beyond)
  double roll_max = 0.35;             ///< [rad]
  double max_slope = 0.2967;          ///< [rad] climbing limit (17 deg)
};

/// A state of the RMP in the map frame.
struct SegwayState {
  double x = 0.0, y = 0.0, heading = 0.0;  ///< [m, m, rad]
  double v = 0.0, omega = 0.0;             ///< [m/s, rad/s]
};

/// Violations of constraints (1)-(6), each >= 0 in its own units.
struct SegwayConstraintViolations {
  double curvature = 0.0;       ///< (1) |omega| - v kappa_max(v) [rad/s]
  double curvature_rate = 0.0;  ///< (1) |omega' - v' kappa| - v sigma_max [rad/s^2]
  double pitch = 0.0;           ///< (3) [rad]
  double roll = 0.0;            ///< (4) [rad]
  double speed = 0.0;           ///< (5) [m/s] (also: slope steeper than max_slope -> v)
  double acceleration = 0.0;    ///< (6) [m/s^2]
  bool ok() const {
    return curvature == 0.0 && curvature_rate == 0.0 && pitch == 0.0 && roll == 0.0 &&
           speed == 0.0 && acceleration == 0.0;
  }
};

/// Where the RMP is on the terrain and how it is tilted.
struct SegwayPose {
  terrain::TangentPlanePatch patch;  ///< the plane under it, along its heading
  double slope = 0.0;                ///< pitch of the patch [rad], > 0 uphill
  double platform_pitch = 0.0;       ///< from the pitch response [rad]
};

/// The Segway RMP on a terrain surface. Immutable; no allocation in its methods.
class SegwayRmpModel {
 public:
  SegwayRmpModel(const terrain::TerrainSurface& surface,
                 SegwayLookups lookups = defaultSegwayLookups(), const SegwayLimits& limits = {});

  const SegwayLimits& limits() const { return limits_; }
  const SegwayLookups& lookups() const { return lookups_; }

  /// kappa_max(v) [1/m].
  double curvatureLimit(double v) const;
  /// The patch, slope and platform pitch at a state with acceleration v' [m/s^2].
  /// std::nullopt off the map or over no data.
  std::optional<SegwayPose> pose(const SegwayState& state, double acceleration) const;
  /// Violations of (1)-(6) at a state and control (v', omega').
  SegwayConstraintViolations check(const SegwayState& state, const Eigen::Vector2d& control,
                                   const SegwayPose& pose) const;
  /// Moves over one patch: from `state`, with constant control (v', omega') for `dt` [s]
  /// (sub-steps of RK4 in the patch's plane), then onto the next patch (the end point's map
  /// position and heading). Returns false off the map or over no data.
  bool propagate(const SegwayState& state, const Eigen::Vector2d& control, double dt,
                 SegwayState& end) const;

 private:
  terrain::TerrainSurface surface_;
  SegwayLookups lookups_;
  SegwayLimits limits_;
};

}  // namespace terratraj::models
