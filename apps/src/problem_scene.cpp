#include "terratraj/apps/problem_scene.hpp"

#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/vehicle_factory.hpp"
#include "terratraj/terrain/terrain_source.hpp"

namespace terratraj::apps {
namespace {

terrain::ElevationMap loadAndResolve(ProblemSpec& problem, const CommandContext& context) {
  context.log->info("{}: loading the terrain", problem.source_file.string());
  terrain::ElevationMap map = terrain::loadTerrain(problem.terrain);
  resolvePosesOnTerrain(problem, map);
  return map;
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
}

}  // namespace terratraj::apps
