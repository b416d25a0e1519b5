#include "terratraj/search/bang_bang_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terratraj::search {

namespace {

// Time to go from v0 to v1 at constant |acceleration| a.
double rampTime(double v0, double v1, double a) { return std::abs(v1 - v0) / a; }
// Distance covered doing so.
double rampDistance(double v0, double v1, double a) {
  return std::abs(v1 * v1 - v0 * v0) / (2 * a);
}

// Accelerate from v0, then brake to v_end (<= the peak), over exactly `distance`, capped at v_max
// (with a cruise in between). Requires distance >= rampDistance(v0, v_end).
double accelerateBrakeTime(double distance, double v0, double v_end, double v_max, double a) {
  const double peak = std::sqrt(0.5 * (2.0 * a * distance + v0 * v0 + v_end * v_end));
  if (peak <= v_max) return rampTime(v0, peak, a) + rampTime(peak, v_end, a);
  const double cruise = distance - rampDistance(v0, v_max, a) - rampDistance(v_max, v_end, a);
  return rampTime(v0, v_max, a) + rampTime(v_max, v_end, a) + std::max(0.0, cruise) / v_max;
}

}  // namespace

double bangBangTime(double distance, double v_start, double v_end_min, double v_end_max,
                    double v_max, double a_max) {
  distance = std::max(0.0, distance);
  if (!(a_max > 0.0) || !(v_max > 0.0)) {
    return distance > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  const double v0 = std::clamp(v_start, 0.0, v_max);
  const double hi = std::clamp(v_end_max, 0.0, v_max);
  const double lo = std::clamp(v_end_min, 0.0, hi);
  if (v0 > hi) {
    // Must brake to hi at least; a longer path than the straight line if it is too short.
    if (distance <= rampDistance(v0, hi, a_max)) return rampTime(v0, hi, a_max);
    return accelerateBrakeTime(distance, v0, hi, v_max, a_max);
  }
  const double reach = std::sqrt(v0 * v0 + 2.0 * a_max * distance);  // full acceleration
  if (reach < lo) return rampTime(v0, lo, a_max);                    // longer path needed
  if (reach <= hi) {
    // Accelerate all the way (capped at v_max, then cruise); the end speed is in range.
    if (reach <= v_max) return rampTime(v0, reach, a_max);
    return rampTime(v0, v_max, a_max) + (distance - rampDistance(v0, v_max, a_max)) / v_max;
  }
  return accelerateBrakeTime(distance, v0, hi, v_max, a_max);
}

double BangBangBound::toGoal(const PlannerState& from, const GoalRegion& goal) const {
  return toGoal(from.position, from.v, goal);
}

double BangBangBound::toGoal(const Eigen::Vector2d& from, double v_from,
                             const GoalRegion& goal) const {
  const double distance = std::max(0.0, (goal.position - from).norm() - goal.position_tolerance);
  return bangBangTime(distance, v_from, goal.v - goal.speed_tolerance,
                      goal.v + goal.speed_tolerance, v_max_, a_max_);
}

}  // namespace terratraj::search
