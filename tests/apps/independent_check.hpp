#pragma once
// A re-check of a written trajectory CSV that shares no code with the toolkit's own checker
// (models::checkTrajectory): the tests hold every `converged` / `solved` file to the contract's
// verdict rules with it. Map and vehicle come from the problem file (ProblemScene).

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/models/trajectory_csv.hpp"

namespace terratraj::apps::testing {

/// Where the trajectory must end, and how closely.
struct GoalTolerance {
  double position_m = 1e-3;
  double heading_rad = 1e-3;
  double speed = 1e-3;
};

/// Every rule the file breaks ("" when it holds them all): finite values, limits at every row
/// (1e-3 relative, 1e-6 absolute), rates between rows, lethal / no-data / off-map cells under
/// the rows and every quarter cell between them, pitch and roll of the vehicle model, the start,
/// and the goal within `goal`.
inline std::string independentCheck(const std::filesystem::path& csv,
                                    const std::filesystem::path& problem_file,
                                    const GoalTolerance& goal) {
  ProblemSpec problem = loadProblem(problem_file);
  std::ostringstream ignore;
  CommandContext context{ignore, ignore, false, std::make_shared<spdlog::logger>("quiet"), nullptr};
  const ProblemScene scene(problem, context);
  const models::Trajectory t = models::readTrajectoryCsv(csv);
  const VehicleLimits& l = problem.vehicle.limits;
  const terrain::ElevationMap& map = scene.map();
  std::ostringstream broken;
  const auto over = [](double value, double limit) { return value > limit * (1.0 + 1e-3) + 1e-6; };
  const auto cellOk = [&](double x, double y) {
    const std::optional<terrain::CellIndex> c = map.geometry().cellAt({x, y});
    return c && !map.isNoData(*c) && !map.isLethal(*c);
  };
  const double pi = 3.14159265358979323846;
  const auto wrap = [pi](double a) { return std::remainder(a, 2.0 * pi); };
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const models::TrajectorySample& s = t.samples[i];
    for (double v : {s.t, s.x, s.y, s.z, s.heading, s.roll, s.pitch, s.v, s.omega, s.curvature}) {
      if (!std::isfinite(v)) broken << "row " << i + 1 << ": not finite; ";
    }
    if (s.v < -1e-6 || over(s.v, l.v_max)) broken << "row " << i + 1 << ": v " << s.v << "; ";
    if (over(std::abs(s.curvature), l.kappa_max)) broken << "row " << i + 1 << ": curvature; ";
    if (over(std::abs(s.omega), l.omega_max)) broken << "row " << i + 1 << ": omega; ";
    if (!cellOk(s.x, s.y)) broken << "row " << i + 1 << ": on a lethal / no-data / off-map cell; ";
    models::AttitudeWorkspace workspace;
    models::AttitudeResult attitude;
    if (scene.vehicle().compute({s.x, s.y, s.heading}, workspace, attitude) !=
        models::AttitudeStatus::kOk) {
      broken << "row " << i + 1 << ": no attitude; ";
    } else {
      if (over(std::abs(attitude.attitude.pitch), l.pitch_max))
        broken << "row " << i + 1 << ": pitch; ";
      if (over(std::abs(attitude.attitude.roll), l.roll_max))
        broken << "row " << i + 1 << ": roll; ";
    }
    if (i == 0) continue;
    const models::TrajectorySample& a = t.samples[i - 1];
    const double dt = s.t - a.t;
    if (!(dt > 0.0)) {
      broken << "row " << i + 1 << ": time does not increase; ";
      continue;
    }
    if (over(std::abs(s.v - a.v) / dt, l.a_max)) broken << "row " << i + 1 << ": a_max; ";
    if (over(std::abs(s.curvature - a.curvature) / dt, l.sigma_max)) {
      broken << "row " << i + 1 << ": sigma_max; ";
    }
    const double d = std::hypot(s.x - a.x, s.y - a.y);
    const int steps = static_cast<int>(std::ceil(4.0 * d / map.geometry().cell)) + 1;
    for (int k = 1; k < steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      if (!cellOk(a.x + f * (s.x - a.x), a.y + f * (s.y - a.y))) {
        broken << "between rows " << i << " and " << i + 1 << ": a lethal / no-data cell; ";
        break;
      }
    }
  }
  if (!t.samples.empty()) {
    const models::TrajectorySample& first = t.samples.front();
    if (std::hypot(first.x - scene.start().x, first.y - scene.start().y) > 1e-6) {
      broken << "does not start at the start; ";
    }
    const models::TrajectorySample& last = t.samples.back();
    if (std::hypot(last.x - scene.goal().x, last.y - scene.goal().y) > goal.position_m) {
      broken << "ends " << std::hypot(last.x - scene.goal().x, last.y - scene.goal().y)
             << " m from the goal; ";
    }
    if (goal.heading_rad < pi &&
        std::abs(wrap(last.heading - scene.goal().heading)) > goal.heading_rad) {
      broken << "ends with the wrong heading; ";
    }
    if (std::abs(last.v - scene.goal().v) > goal.speed) broken << "ends at the wrong speed; ";
  }
  return broken.str();
}

}  // namespace terratraj::apps::testing
