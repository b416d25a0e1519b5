#pragma once
// PathConstraints: the vehicle limits as inequalities g <= 0 at one point of a trajectory, in
// a smooth form for optimisers, and their violation in each limit's own units for reports.
//
// Rows (each g <= 0):
//   speed:          v - v_max;  -v  (forward driving)
//   acceleration:   +-v' - a_max
//   yaw rate:       +-omega - omega_max
//   curvature:      +-omega - kappa_max v           (|kappa| <= kappa_max, kappa = omega / v)
//   curvature rate: +-(omega' v - omega v') - sigma_max v^2   (|d kappa / dt| <= sigma_max)
//   pitch, roll:    +-pitch - pitch_max, +-roll - roll_max
//   tables:         v - table_pitch(pitch), v - table_rc(roll, kappa)   (smooth look-ups)
//   Segway RMP:     v - v_max(slope), +-v' - a_max(slope), +-platform_pitch(v', slope) - pitch_max
//                   (SpeedTables::segway; the C1 optimiser versions of its look-ups, slope = the
//                   terrain pitch along the heading; models::SegwayLookups)
// The point's variables are p = (x, y, heading, v, omega, v', omega'); roll and pitch enter
// through the terrain-following model's attitude Jacobian.

#include <Eigen/Core>
#include <string>
#include <string_view>

#include "terratraj/models/attitude.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::ocp {

/// One point of a trajectory.
struct PathPoint {
  double t = 0.0;
  Eigen::Vector3d state = Eigen::Vector3d::Zero();  ///< (x, y, heading)
  models::AttitudeResult attitude;                  ///< with its Jacobian
  double v = 0.0, omega = 0.0, v_dot = 0.0, omega_dot = 0.0;
};

/// Number of variables of a PathPoint the constraints depend on.
inline constexpr int kPathVariables = 7;
/// Rows the Segway RMP's look-ups add (SpeedTables::segway).
inline constexpr int kSegwayPathRows = 5;

/// The largest violation over a trajectory.
struct LimitViolation {
  double amount = 0.0;  ///< >= 0, in the limit's units (m/s, m/s^2, rad/s, 1/m, 1/(m s), rad)
  std::string limit;    ///< "v_max", "pitch_max", ... (empty when none is violated)
  double t = 0.0;       ///< where [s]
};

/// Whether the row named `limit` (PathConstraints::name) is identically 0 at a point standing
/// still with no yaw rate (v = omega = 0), whatever the accelerations: v_min (-v), kappa_max
/// (+-omega - kappa_max v) and sigma_max (+-(omega' v - omega v') - sigma_max v^2).
bool vanishesAtRest(std::string_view limit);

/// The limits of one vehicle as path constraints.
class PathConstraints {
 public:
  /// `segway_bound_scale` in (0, 1]: the Segway's slope speed and acceleration bounds times
  /// this (a margin for what happens between the points where the rows are held).
  PathConstraints(const models::VehicleLimits& limits, const SpeedTables& tables,
                  double segway_bound_scale = 1.0);

  /// Rows per point.
  int count() const { return count_; }
  /// The limit a row enforces ("v_max", ...).
  const char* name(int row) const;

  /// g (count() values) at the point; when `jacobian` is not null it receives
  /// d g / d p (count() x kPathVariables, row-major in the matrix given).
  void evaluate(const PathPoint& point, double* values,
                Eigen::Matrix<double, Eigen::Dynamic, kPathVariables>* jacobian) const;

  /// Folds the point's violations into `worst` (each in its limit's own units). Not the
  /// Segway's rows: the verdict (models::TrajectoryRequirements::segway) judges those by the
  /// look-ups' grids, between samples.
  void accumulateViolation(const PathPoint& point, LimitViolation& worst) const;

 private:
  void evaluateSegway(const PathPoint& point, double* values,
                      Eigen::Matrix<double, Eigen::Dynamic, kPathVariables>* jacobian) const;

  models::VehicleLimits limits_;
  SpeedTables tables_;
  int count_;
  double segway_bound_scale_;
  int pitch_table_row_ = -1, roll_curvature_row_ = -1, segway_row_ = -1;  // -1: no such rows
};

}  // namespace terratraj::ocp
