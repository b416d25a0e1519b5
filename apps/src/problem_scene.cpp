#include "terratraj/apps/problem_scene.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/vehicle_factory.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_source.hpp"

namespace terratraj::apps {
namespace {

terrain::ElevationMap loadAndResolve(ProblemSpec& problem, const CommandContext& context) {
  context.log->info("{}: loading the terrain", problem.source_file.string());
  terrain::ElevationMap map = terrain::loadTerrain(problem.terrain);
  resolvePosesOnTerrain(problem, map);
  return map;
}

constexpr double kDegreesPerRadian = 57.29577951308232;

std::string angleText(double radians) {
  std::ostringstream text;
  text << radians * kDegreesPerRadian << " deg (" << radians << " rad)";
  return text.str();
}

// The vehicle at rest at a boundary pose must hold the pitch and roll limits: the trajectory's
// first (or last) row is there.
void checkAttitudeLimits(const models::AttitudeResult& attitude, const char* which,
                         const ProblemSpec& problem) {
  const VehicleLimits& l = problem.vehicle.limits;
  const std::string where = problem.source_file.string() + ": " + which;
  const BoundaryState& s = std::string(which) == "start" ? problem.start : problem.goal;
  std::ostringstream pose;
  pose << " at (" << s.x << ", " << s.y << ") m, heading " << angleText(s.heading);
  if (std::abs(attitude.attitude.pitch) > l.pitch_max) {
    throw InputError(where + ": the " + vehicleModelName(problem.vehicle.model) +
                     " vehicle's pitch" + pose.str() + " is " + angleText(attitude.attitude.pitch) +
                     ", beyond vehicle.limits.pitch_max_deg = " + angleText(l.pitch_max) +
                     ": move the " + which + " or raise the limit");
  }
  if (std::abs(attitude.attitude.roll) > l.roll_max) {
    throw InputError(where + ": the " + vehicleModelName(problem.vehicle.model) +
                     " vehicle's roll" + pose.str() + " is " + angleText(attitude.attitude.roll) +
                     ", beyond vehicle.limits.roll_max_deg = " + angleText(l.roll_max) +
                     ": move the " + which + " or raise the limit");
  }
}

}  // namespace

ProblemScene::ProblemScene(ProblemSpec& problem, const CommandContext& context)
    : map_(loadAndResolve(problem, context)), surface_(map_, terrain::Interpolation::kBicubic) {
  if (problem.vehicle.tables.pitch) {
    pitch_table_ = models::readPitchTable(*problem.vehicle.tables.pitch);
  }
  if (problem.vehicle.tables.roll_curvature) {
    roll_table_ = models::readRollCurvatureTable(*problem.vehicle.tables.roll_curvature);
  }
  vehicle_ = makeTerrainFollowingModel(problem.vehicle.model, surface_);
  start_attitude_ = restingAttitude(*vehicle_, problem.start, "start", problem);
  goal_attitude_ = restingAttitude(*vehicle_, problem.goal, "goal", problem);
  checkAttitudeLimits(start_attitude_, "start", problem);
  checkAttitudeLimits(goal_attitude_, "goal", problem);
}

}  // namespace terratraj::apps
