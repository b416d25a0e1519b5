#include "terratraj/apps/terrain_commands.hpp"

#include "terratraj/apps/plan_command.hpp"
#include "terratraj/apps/solve_command.hpp"

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

// Wall-clock budget of the demo's PRM plan [s].
constexpr double kDemoPlanTimeLimitS = 0.5;

constexpr double kRadToDeg = 57.29577951308232;

nlohmann::json extentJson(double x_min, double y_min, double x_max, double y_max) {
  return {{"x_min", x_min}, {"y_min", y_min}, {"x_max", x_max}, {"y_max", y_max}};
}

void writeJsonFile(const nlohmann::json& json, const std::filesystem::path& path) {
  std::ofstream file(path);
  file << json.dump(2) << '\n';
  if (!file) throw InputError(path.string() + ": cannot be written");
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

int runDemo(const DemoOptions& options, CommandContext& context) {
  createDirectories(options.out_dir);
  const std::filesystem::path tif = options.out_dir / "terrain.tif";
  const std::filesystem::path summary_file = options.out_dir / "summary.json";
  context.log->info("demo: generating '{}' terrain, {} x {} cells of {} m, seed {}",
                    terrain::terrainKindName(options.generator.kind), options.generator.cols,
                    options.generator.rows, options.generator.cell, options.generator.seed);
  const terrain::ElevationMap map = terrain::generateTerrain(options.generator);
  terrain::saveGeoTiff(map, tif);
  context.log->info("demo: wrote {}", tif.string());
  const terrain::TerrainStatistics stats = terrain::computeTerrainStatistics(map);
  nlohmann::json summary{
      {"status", "ok"},
      {"terrain",
       {{"kind", terrain::terrainKindName(options.generator.kind)},
        {"seed", options.generator.seed},
        {"file", tif.string()},
        {"statistics", terrainStatisticsJson(stats)}}},
  };
  const std::filesystem::path solve_file = options.out_dir / "solve.csv";
  summary["solve"] = solveDemoProblem(map, solve_file, context);
  const std::filesystem::path plan_file = options.out_dir / "plan.csv";
  summary["plan"] = planDemoProblem(map, plan_file, kDemoPlanTimeLimitS, context);
  writeJsonFile(summary, summary_file);
  context.log->info("demo: wrote {}", summary_file.string());
  if (context.json) {
    context.out << summary.dump(2) << '\n';
  } else {
    context.out << "terratraj demo: generated terrain '"
                << terrain::terrainKindName(options.generator.kind) << "' (seed "
                << options.generator.seed << ")\n"
                << terrainStatisticsText(stats);
    const nlohmann::json& solve = summary["solve"];
    context.out << "solve (newton, rocker_bogie, 6.2 m, slope dwell alpha 1): "
                << solve["status"].get<std::string>() << " in " << solve["iterations"]
                << " iterations, " << solve["solve_time_ms"].get<double>() << " ms";
    if (solve["final_time_s"].is_number()) {
      context.out << "; t_f " << solve["final_time_s"].get<double>() << " s, terminal error "
                  << solve["terminal_error"]["position_m"].get<double>() << " m";
    }
    const nlohmann::json& plan = summary["plan"];
    context.out << "\nplan (prm, point vehicle, " << kDemoPlanTimeLimitS
                << " s): " << plan["status"].get<std::string>();
    if (plan["best_cost_s"].is_number()) {
      context.out << "; first solution " << plan["first_solution_ms"].get<double>()
                  << " ms, best cost " << plan["best_cost_s"].get<double>() << " s, "
                  << plan["nodes"] << " nodes";
    }
    context.out << "\n  files      " << tif.string() << ", " << summary_file.string() << ", "
                << solve_file.string();
    if (plan["best_cost_s"].is_number()) context.out << ", " << plan_file.string();
    context.out << '\n';
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
