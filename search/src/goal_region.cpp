#include "terratraj/search/goal_region.hpp"

#include <cmath>

namespace terratraj::search {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double wrapAngle(double angle) {
  if (!std::isfinite(angle)) return angle;
  double wrapped = std::remainder(angle, 2.0 * kPi);  // in [-pi, pi]
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

double GoalRegion::positionError(const PlannerState& state) const {
  return (state.position - position).norm();
}

double GoalRegion::headingError(const PlannerState& state) const {
  return std::abs(wrapAngle(state.heading - heading));
}

bool GoalRegion::contains(const PlannerState& state) const {
  return positionError(state) <= position_tolerance &&
         (heading_tolerance >= kPi || headingError(state) <= heading_tolerance) &&
         std::abs(state.v - v) <= speed_tolerance;
}

}  // namespace terratraj::search
