#pragma once
// GoalRegion: the set of states a plan may end in (position, heading and speed tolerances).

#include <Eigen/Core>

#include "terratraj/search/planner_state.hpp"

namespace terratraj::search {

/// Default tolerances of a goal region.
inline constexpr double kDefaultGoalPositionTolerance = 0.5;  ///< [m]
inline constexpr double kDefaultGoalHeadingTolerance = 0.35;  ///< [rad] (about 20 degrees)
inline constexpr double kDefaultGoalSpeedTolerance = 0.1;     ///< [m/s]

/// A goal state and how far from it a plan may end. Tolerances are > 0; a heading tolerance
/// >= pi accepts any heading.
struct GoalRegion {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();         ///< local map frame [m]
  double heading = 0.0;                                       ///< map heading [rad]
  double v = 0.0;                                             ///< speed [m/s]
  double position_tolerance = kDefaultGoalPositionTolerance;  ///< horizontal distance [m]
  double heading_tolerance = kDefaultGoalHeadingTolerance;    ///< |wrapped difference| [rad]
  double speed_tolerance = kDefaultGoalSpeedTolerance;        ///< |difference| [m/s]

  /// Whether a state lies in the region (all three tolerances hold, borders included).
  bool contains(const PlannerState& state) const;
  /// Horizontal distance from the goal position [m].
  double positionError(const PlannerState& state) const;
  /// |heading - goal heading| wrapped to [0, pi] [rad].
  double headingError(const PlannerState& state) const;
};

/// An angle wrapped to (-pi, pi] [rad].
double wrapAngle(double angle);

}  // namespace terratraj::search
