#include "terratraj/search/planning_problem.hpp"

#include <cmath>
#include <sstream>

namespace terratraj::search {

namespace {

std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Message for a pose the vehicle cannot occupy, or std::nullopt.
std::optional<std::string> checkPose(const PlanningProblem& problem, const char* which,
                                     const Eigen::Vector2d& position, double heading, double v) {
  const terrain::ElevationMap& map = *problem.map;
  const std::string where =
      std::string(which) + " (" + number(position.x()) + ", " + number(position.y()) + ") m";
  if (!std::isfinite(position.x()) || !std::isfinite(position.y()) || !std::isfinite(heading)) {
    return where + ": not a finite pose";
  }
  const std::optional<terrain::CellIndex> cell = map.geometry().cellAt(position);
  if (!cell) return where + ": off the map";
  if (map.isNoData(*cell)) return where + ": on a no-data cell";
  if (map.isLethal(*cell)) return where + ": on a lethal cell";
  models::AttitudeWorkspace workspace;
  models::AttitudeResult attitude;
  if (problem.vehicle->compute({position.x(), position.y(), heading}, workspace, attitude) !=
      models::AttitudeStatus::kOk) {
    return where + ": the " + std::string(problem.vehicle->name()) +
           " vehicle cannot rest on the terrain there";
  }
  const models::VehicleLimits& l = problem.limits;
  if (std::abs(attitude.attitude.pitch) > l.pitch_max) {
    return where + ": pitch " + number(attitude.attitude.pitch) +
           " rad exceeds limits.pitch_max = " + number(l.pitch_max) + " rad";
  }
  if (std::abs(attitude.attitude.roll) > l.roll_max) {
    return where + ": roll " + number(attitude.attitude.roll) +
           " rad exceeds limits.roll_max = " + number(l.roll_max) + " rad";
  }
  if (!(v >= 0.0) || v > l.v_max) {
    return std::string(which) + ".v: " + number(v) +
           " m/s is outside [0, limits.v_max = " + number(l.v_max) + "]";
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> PlanningProblem::validate() const {
  const models::VehicleLimits& l = limits;
  const std::pair<const char*, double> positive[] = {
      {"limits.v_max", l.v_max},
      {"limits.a_max", l.a_max},
      {"limits.omega_max", l.omega_max},
      {"limits.kappa_max", l.kappa_max},
      {"limits.sigma_max", l.sigma_max},
      {"limits.pitch_max", l.pitch_max},
      {"limits.roll_max", l.roll_max},
      {"goal.position_tolerance", goal.position_tolerance},
      {"goal.heading_tolerance", goal.heading_tolerance},
      {"goal.speed_tolerance", goal.speed_tolerance}};
  for (const auto& [name, value] : positive) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      return std::string(name) + ": must be a positive finite number (got " + number(value) + ")";
    }
  }
  if (auto error = checkPose(*this, "start", start.position, start.heading, start.v)) return error;
  if (auto error = checkPose(*this, "goal", goal.position, goal.heading, goal.v)) return error;
  if (!std::isfinite(start.curvature) || std::abs(start.curvature) > l.kappa_max) {
    return "start.curvature: |" + number(start.curvature) +
           "| 1/m exceeds limits.kappa_max = " + number(l.kappa_max) + " 1/m";
  }
  if (std::abs(start.omega()) > l.omega_max) {
    return "start.omega: |" + number(start.omega()) +
           "| rad/s exceeds limits.omega_max = " + number(l.omega_max) + " rad/s";
  }
  return std::nullopt;
}

}  // namespace terratraj::search
