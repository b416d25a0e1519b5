#include "terratraj/ocp/boundary_value_problem.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {

bool standsStill(const VehicleState& state) { return std::abs(state.v) <= kRestSpeed; }

double SpeedTables::speedCap(const models::Attitude& attitude, double curvature,
                             double v_max) const {
  double cap = v_max;
  if (pitch != nullptr) cap = std::min(cap, pitch->lookup(attitude.pitch));
  if (roll_curvature != nullptr)
    cap = std::min(cap, roll_curvature->lookup(attitude.roll, curvature));
  if (segway != nullptr) cap = std::min(cap, segway->bounds.speedLimit(attitude.pitch));
  return std::max(cap, 0.0);
}

double SpeedTables::accelerationCap(const models::Attitude& attitude, double a_max) const {
  if (segway == nullptr) return a_max;
  return std::clamp(segway->bounds.accelerationLimit(attitude.pitch), 0.0, a_max);
}

double wrapAngle(double angle) {
  constexpr double kPi = 3.14159265358979323846;
  double wrapped = std::remainder(angle, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

std::optional<std::string> validateBoundaryStates(const BoundaryValueProblem& problem) {
  const auto finite = [](const VehicleState& s) {
    return std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.heading) &&
           std::isfinite(s.v) && std::isfinite(s.omega);
  };
  if (!finite(problem.start)) return "start state is not finite";
  if (!finite(problem.goal)) return "goal state is not finite";
  if (!(problem.cost.alpha >= 0.0) || !std::isfinite(problem.cost.alpha)) {
    return "cost alpha must be finite and >= 0";
  }
  return std::nullopt;
}

std::optional<std::string> validateProblem(const BoundaryValueProblem& problem) {
  if (std::optional<std::string> why = validateBoundaryStates(problem)) return why;
  if (problem.orders.yaw_rate < 1 || problem.orders.yaw_rate > 8) {
    return "yaw-rate polynomial order " + std::to_string(problem.orders.yaw_rate) +
           " is outside [1, 8]";
  }
  if (problem.orders.speed < 1 || problem.orders.speed > 8) {
    return "speed polynomial order " + std::to_string(problem.orders.speed) + " is outside [1, 8]";
  }
  if (problem.orders.yaw_rate + problem.orders.speed - 1 < 3) {
    return "the controls have " +
           std::to_string(problem.orders.yaw_rate + problem.orders.speed - 1) +
           " unknowns, fewer than the 3 terminal constraints (x, y, heading): raise "
           "solver.yaw_rate_order";
  }
  if (problem.orders.speed == 1 && problem.start.v == 0.0 && problem.goal.v == 0.0) {
    return "the speed polynomial of order 1 from start.v = 0 to goal.v = 0 is zero throughout: "
           "the vehicle cannot move (raise solver.speed_order to 2 or more, or give a "
           "non-zero start or goal speed)";
  }
  return std::nullopt;
}

}  // namespace terratraj::ocp
