#pragma once
// The bang-bang lower bound L-(s, s') of 001_... IV.A: the minimum time between two states in
// an obstacle-free world where the vehicle may accelerate and brake at a_max up to v_max along
// a path at least as long as the straight line between them. Heading and curvature are ignored,
// so it never exceeds the time of any feasible trajectory (a test checks it against the
// steering): the planner orders candidate nodes by it and prunes with it (branch and bound).

#include <Eigen/Core>

#include "terratraj/search/goal_region.hpp"
#include "terratraj/search/planner_state.hpp"

namespace terratraj::search {

/// Minimum time [s] for a point moving along a path of length >= `distance` [m], starting at
/// speed `v_start`, ending at a speed in [v_end_min, v_end_max], with 0 <= v <= v_max [m/s] and
/// |dv/dt| <= a_max [m/s^2]. Speeds are clamped to [0, v_max] first (and v_end_min to at most
/// v_end_max). When the straight distance is too short to reach the end speed range the path
/// is taken longer (the bound is then the pure acceleration / braking time). Returns +infinity
/// only for a_max <= 0 or v_max <= 0 with a non-zero distance.
double bangBangTime(double distance, double v_start, double v_end_min, double v_end_max,
                    double v_max, double a_max);

/// L-(s, s') for a vehicle's speed and acceleration limits.
class BangBangBound {
 public:
  /// v_max [m/s] and a_max [m/s^2], both > 0.
  BangBangBound(double v_max, double a_max) : v_max_(v_max), a_max_(a_max) {}

  /// Lower bound [s] from `from` to the position `to` [m], arriving at a speed in
  /// [v_end_min, v_end_max] [m/s].
  double toPoint(const PlannerState& from, const Eigen::Vector2d& to, double v_end_min,
                 double v_end_max) const {
    return bangBangTime((to - from.position).norm(), from.v, v_end_min, v_end_max, v_max_, a_max_);
  }
  /// Lower bound [s] from `from` to any state of the goal region.
  double toGoal(const PlannerState& from, const GoalRegion& goal) const;
  /// Lower bound [s] from the position `from` at speed `v_from` to the goal region.
  double toGoal(const Eigen::Vector2d& from, double v_from, const GoalRegion& goal) const;

  /// The speed limit [m/s] and acceleration limit [m/s^2] the bound uses.
  double vMax() const { return v_max_; }
  double aMax() const { return a_max_; }

 private:
  double v_max_;
  double a_max_;
};

}  // namespace terratraj::search
