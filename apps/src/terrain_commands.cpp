#include "terratraj/apps/terrain_commands.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/raster_io.hpp"

namespace terratraj::apps {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

nlohmann::json extentJson(double x_min, double y_min, double x_max, double y_max) {
  return {{"x_min", x_min}, {"y_min", y_min}, {"x_max", x_max}, {"y_max", y_max}};
}

void createDirectories(const std::filesystem::path& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error)
    throw InputError(dir.string() + ": cannot create the folder (" + error.message() + ")");
}

}  // namespace

nlohmann::json terrainStatisticsJson(const terrain::TerrainStatistics& stats) {
  const terrain::GridGeometry& g = stats.geometry;
  const Eigen::Vector2d world_min = g.toWorld(Eigen::Vector2d::Zero());
  const Eigen::Vector2d world_max = g.toWorld(Eigen::Vector2d(g.width(), g.height()));
  nlohmann::json json{
      {"rows", g.rows},
      {"cols", g.cols},
      {"cell_m", g.cell},
      {"cells", g.cellCount()},
      {"extent_local_m", extentJson(0.0, 0.0, g.width(), g.height())},
      {"extent_world_m", extentJson(world_min.x(), world_min.y(), world_max.x(), world_max.y())},
      {"valid_cells", stats.valid_cells},
      {"no_data_cells", stats.no_data_cells},
      {"lethal_cells", stats.lethal_cells},
      {"obstacle_clusters", stats.obstacle_clusters},
      {"height_m",
       {{"min", stats.min_height}, {"max", stats.max_height}, {"mean", stats.mean_height}}},
      {"slope_rad",
       {{"mean", stats.mean_slope}, {"p95", stats.p95_slope}, {"max", stats.max_slope}}},
  };
  return json;
}

std::string terrainStatisticsText(const terrain::TerrainStatistics& stats) {
  const terrain::GridGeometry& g = stats.geometry;
  const Eigen::Vector2d world_max = g.toWorld(Eigen::Vector2d(g.width(), g.height()));
  std::ostringstream text;
  text << std::fixed << std::setprecision(2);
  text << "  size       " << g.cols << " x " << g.rows << " cells (cols x rows), cell " << g.cell
       << " m\n";
  text << "  extent     " << g.width() << " x " << g.height() << " m; world x ["
       << g.world_origin.x() << ", " << world_max.x() << "], y [" << g.world_origin.y() << ", "
       << world_max.y() << "]\n";
  text << "  height     " << stats.min_height << " .. " << stats.max_height << " m (mean "
       << stats.mean_height << ")\n";
  const double percent = 100.0 * static_cast<double>(stats.no_data_cells) / g.cellCount();
  text << "  no-data    " << stats.no_data_cells << " cells (" << std::setprecision(1) << percent
       << " %)\n";
  text << "  slope      mean " << stats.mean_slope * kRadToDeg << " deg, p95 "
       << stats.p95_slope * kRadToDeg << " deg, max " << stats.max_slope * kRadToDeg << " deg\n";
  text << "  lethal     " << stats.lethal_cells << " cells in " << stats.obstacle_clusters
       << " clusters\n";
  return text.str();
}

int runTerrainInfo(const TerrainInfoOptions& options, CommandContext& context) {
  terrain::RasterLoadOptions load;
  load.cell = options.cell;
  load.z_scale = options.z_scale;
  const terrain::ElevationMap map = terrain::loadElevationMap(options.file, load);
  const terrain::TerrainStatistics stats = terrain::computeTerrainStatistics(map);
  if (context.json) {
    nlohmann::json json = terrainStatisticsJson(stats);
    json["status"] = "ok";
    json["file"] = options.file.string();
    context.out << json.dump(2) << '\n';
  } else {
    context.out << options.file.string() << '\n' << terrainStatisticsText(stats);
  }
  return kExitSuccess;
}

int runTerrainGenerate(const TerrainGenerateOptions& options, CommandContext& context) {
  context.log->info("generating '{}' terrain, {} x {} cells of {} m, seed {}",
                    terrain::terrainKindName(options.generator.kind), options.generator.cols,
                    options.generator.rows, options.generator.cell, options.generator.seed);
  const terrain::ElevationMap map = terrain::generateTerrain(options.generator);
  if (options.out.has_parent_path()) createDirectories(options.out.parent_path());
  terrain::saveGeoTiff(map, options.out);
  const terrain::TerrainStatistics stats = terrain::computeTerrainStatistics(map);
  if (context.json) {
    nlohmann::json json = terrainStatisticsJson(stats);
    json["status"] = "ok";
    json["kind"] = terrain::terrainKindName(options.generator.kind);
    json["seed"] = options.generator.seed;
    json["file"] = options.out.string();
    context.out << json.dump(2) << '\n';
  } else {
    context.out << "wrote " << options.out.string() << '\n' << terrainStatisticsText(stats);
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
