#pragma once
// checkTrajectory(): re-checks a finished trajectory against every limit, table and the map,
// independently of whatever produced it (a solver, a planner, another tool). It reads only the
// trajectory's samples (the contract's CSV columns), differentiates them by finite
// differences, recomputes the attitude with the vehicle model, and walks the map between
// samples; it shares no code with the solvers' or planners' own checks.
//
// Checked at every sample: finite values; 0 <= v <= v_max; |curvature| <= kappa_max;
// |omega| <= omega_max and omega = v curvature; pitch and roll recomputed by the attitude
// model within pitch_max / roll_max (and equal to the file's columns); v within the tables; no
// lethal, no-data or off-map cell under the sample.
// Between consecutive samples: time strictly increasing; |dv/dt| <= a_max; |d curvature/dt| <=
// sigma_max; horizontal motion no longer than the speeds allow; motion along the heading (the
// chord's direction within the headings the arc can take: its ends', widened when the
// curvature changes sign between them, as in a planner's clothoid S-bend); no lethal, no-data
// or off-map cell under points every cell / 8 on the segment (the planners' footprint: the
// vehicle's reference point swept along its path).
// With the Segway RMP's look-ups (TrajectoryRequirements::segway; 001_... III.C): v within the
// slope's speed bound at every sample; between samples the acceleration within the slope's
// a_max and the platform pitch it causes (the pitch response of acceleration and slope) within
// pitch_max.
// Optionally the first sample is the start and the last lies within the goal's tolerances.
//
// This is the check behind every verdict (trajectory_verdict.hpp): the contract's `converged`
// and `solved` mean it passes on the written CSV.

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::models {

/// One broken rule: which, by how much (in the limit's own units) and where.
struct CheckViolation {
  /// "v_max", "a_max", "omega_max", "kappa_max", "sigma_max", "pitch_max", "roll_max",
  /// "table_pitch", "table_roll_curvature", "lethal", "no_data", "off_map", "goal_position",
  /// "goal_heading", "goal_speed", "start_position", "start_speed", "time_order", "motion",
  /// "heading_of_motion", "pitch_column", "roll_column", "attitude", "finite", "v_min",
  /// "omega_equals_v_curvature", "empty", "segway_slope_v_max", "segway_slope_a_max",
  /// "segway_platform_pitch".
  std::string limit;
  double amount = 0.0;     ///< excess over the limit, in its units (> 0); 1 for map and structure
  double value = 0.0;      ///< the value found (limit units; 0 for map and structure rules)
  double bound = 0.0;      ///< the limit it was held against (limit units)
  std::size_t sample = 0;  ///< index of the (first) sample involved, 0-based
  double t = 0.0;          ///< that sample's time [s] (0 when not finite)
};

/// The outcome of a check.
struct CheckReport {
  std::vector<CheckViolation> violations;  ///< the worst violation of each rule, one per rule
  double max_violation = 0.0;              ///< largest amount (0 when all hold)
  bool ok() const { return violations.empty(); }
  /// The violation of `limit`, or null.
  const CheckViolation* find(const std::string& limit) const;
  /// "ok" or one line per violation ("v_max: 1.003 m/s > 1 m/s (by 0.003) at row 12, t = 0.24
  /// s"); rows count the CSV's data rows from 1, angles are also given in degrees.
  std::string summary() const;
};

/// Relative and absolute slack of the checks. The defaults are the contract's verdict:
/// every limit within 1e-3 relative and 1e-6 absolute.
struct CheckTolerances {
  double relative = 1e-3;  ///< fraction of each limit
  double absolute = 1e-6;  ///< in the limit's units
  double heading = 0.05;   ///< direction of motion vs heading [rad]
  double attitude = 1e-4;  ///< recomputed pitch / roll vs the columns [rad] (iterative models)
};

/// Where a checked trajectory must start.
struct StartRequirement {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< local map frame [m]
  double v = 0.0;                                      ///< [m/s]
  double position_tolerance = 1e-6;                    ///< [m]
  double speed_tolerance = 1e-6;                       ///< [m/s]
};

/// Where a checked trajectory must end.
struct GoalRequirement {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< local map frame [m]
  double heading = 0.0;                                ///< [rad]
  double v = 0.0;                                      ///< [m/s]
  double position_tolerance = 1e-3;                    ///< horizontal distance [m], > 0
  double heading_tolerance = 1e-3;  ///< |wrapped difference| [rad], > 0; >= pi: any heading
  double speed_tolerance = 1e-3;    ///< |difference| [m/s], > 0
};

/// Everything a trajectory is held to. The pointers must outlive the check; `vehicle` is
/// required, the tables optional; `map` (whose view the vehicle's surface is) supplies the map
/// rules (lethal, no-data, off-map), which are skipped when it is null (a vehicle model without
/// a map, such as ocp::FlatGroundModel).
struct TrajectoryRequirements {
  const terrain::ElevationMap* map = nullptr;
  const TerrainFollowingModel* vehicle = nullptr;
  VehicleLimits limits;
  const PitchSpeedTable* pitch_table = nullptr;                   ///< optional: v_max by pitch
  const RollCurvatureSpeedTable* roll_curvature_table = nullptr;  ///< optional
  /// Optional: the Segway RMP's look-ups, whose rules then apply (see the top of this file).
  const SegwayLookups* segway = nullptr;
  std::optional<StartRequirement> start;  ///< absent: the first sample is not checked
  std::optional<GoalRequirement> goal;    ///< absent: the last sample is not checked
  CheckTolerances tolerances;
};

/// Checks `trajectory` against `requirements` (see the top of this file). Never throws (except
/// std::bad_alloc); a trajectory that cannot be checked (empty, NaN) is reported as a
/// violation of "empty" / "finite".
CheckReport checkTrajectory(const Trajectory& trajectory,
                            const TrajectoryRequirements& requirements);

}  // namespace terratraj::models
