#pragma once
// BoundaryValueProblem: start and goal states, the cost, the control parametrisation and the
// vehicle limits of one trajectory-generation problem (004_... 2). Plain values; the terrain
// and vehicle model are passed to the solvers separately.

#include <optional>
#include <string>

#include "terratraj/models/attitude.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/models/velocity_table.hpp"

namespace terratraj::ocp {

/// A boundary state in the local map frame: position [m], heading [rad], body speed [m/s] and
/// yaw rate [rad/s].
struct VehicleState {
  double x = 0.0;
  double y = 0.0;
  double heading = 0.0;
  double v = 0.0;
  double omega = 0.0;
};

/// Speeds at or below this are rest [m/s].
inline constexpr double kRestSpeed = 1e-9;

/// Whether the vehicle stands still in `state` (|v| <= kRestSpeed). At an end standing still
/// the curvature is the limit omega' / v', which the solvers hold with rows of their own.
bool standsStill(const VehicleState& state);

/// What the optimiser minimises.
enum class CostKind {
  kTime,        ///< J = t_f (004_... eq. 16)
  kSlopeDwell,  ///< J = integral of 1 + alpha (roll^2 + pitch^2) dt (004_... eq. 17)
};

/// The cost functional.
struct CostFunctional {
  CostKind kind = CostKind::kTime;
  double alpha = 0.0;  ///< slope-dwell weight [1/rad^2], >= 0
};

/// Orders of the control polynomials (004_... eq. 12): yaw rate and speed are polynomials in
/// t / t_f of these orders; the top coefficient of each is fixed by the terminal yaw rate and
/// speed (eq. 13), the others are unknowns.
struct ControlOrders {
  int yaw_rate = 4;  ///< in [1, 8]; 4 as in the paper
  int speed = 1;     ///< in [1, 8]; 1 as in the paper (speed linear from start.v to goal.v)
};

/// Optional kinodynamic look-up tables limiting speed (003_...); not owned.
struct SpeedTables {
  const models::PitchSpeedTable* pitch = nullptr;
  const models::RollCurvatureSpeedTable* roll_curvature = nullptr;
  /// The Segway RMP's look-ups (001_... III.C: slope speed and acceleration bounds, platform
  /// pitch): every verdict checks them (models::TrajectoryRequirements::segway). The
  /// transcriptions hold them as constraints through TranscriptionModelOptions::segway.
  const models::SegwayLookups* segway = nullptr;

  /// The tightest speed bound [m/s] of the tables at this attitude [rad] (pitch: the slope along
  /// the heading) and curvature [1/m], or `v_max` when no table bounds it lower. 0 where a table
  /// forbids driving (the Segway beyond its drivable slope).
  double speedCap(const models::Attitude& attitude, double curvature, double v_max) const;
  /// The tightest acceleration bound [m/s^2] at this attitude: the Segway's by slope, else
  /// `a_max`.
  double accelerationCap(const models::Attitude& attitude, double a_max) const;
};

/// One boundary-value problem.
struct BoundaryValueProblem {
  VehicleState start;
  VehicleState goal;
  CostFunctional cost;
  ControlOrders orders;
  models::VehicleLimits limits;
  SpeedTables tables;
};

/// Why a problem cannot be posed (orders out of range, non-finite values, a speed profile that
/// is zero throughout), or std::nullopt when it can.
std::optional<std::string> validateProblem(const BoundaryValueProblem& problem);
/// The part of validateProblem that does not depend on the control parametrisation (finite
/// states, alpha >= 0): what direct transcription needs. Start == goal is not an error
/// (start_at_goal.hpp).
std::optional<std::string> validateBoundaryStates(const BoundaryValueProblem& problem);

/// Heading difference a - b wrapped to (-pi, pi] [rad].
double wrapAngle(double angle);

}  // namespace terratraj::ocp
