#include "terratraj/apps/problem_scene.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_source.hpp"

namespace terratraj::apps {
namespace {

terrain::ElevationMap loadTerrain(const ProblemSpec& problem, const CommandContext& context) {
  context.log->info("{}: loading the terrain", problem.source_file.string());
  return terrain::loadTerrain(problem.terrain);
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
                         const BoundaryState& s, const ProblemSpec& problem) {
  const VehicleLimits& l = problem.vehicle.limits;
  const std::string where = problem.source_file.string() + ": " + which;
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

ProblemScene::ProblemScene(const ProblemSpec& problem, const CommandContext& context)
    : map_(loadTerrain(problem, context)),
      poses_(resolvePoses(problem, map_)),
      surface_(map_, problem.terrain.interpolation) {
  if (problem.vehicle.tables.pitch) {
    pitch_table_ = models::readPitchTable(*problem.vehicle.tables.pitch);
  }
  if (problem.vehicle.tables.roll_curvature) {
    roll_table_ = models::readRollCurvatureTable(*problem.vehicle.tables.roll_curvature);
  }
  if (problem.vehicle.model == VehicleModelKind::kSegwayRmp) {
    segway_lookups_ = models::defaultSegwayLookups();
    search_pitch_table_ = models::slopeSpeedTable(segway_lookups_->bounds, pitchTable());
  }
  vehicle_ = makeTerrainFollowingModel(problem.vehicle.model, surface_);
  start_attitude_ = restingAttitude(*vehicle_, poses_.start, "start", problem);
  goal_attitude_ = restingAttitude(*vehicle_, poses_.goal, "goal", problem);
  checkAttitudeLimits(start_attitude_, "start", poses_.start, problem);
  checkAttitudeLimits(goal_attitude_, "goal", poses_.goal, problem);
}

}  // namespace terratraj::apps
