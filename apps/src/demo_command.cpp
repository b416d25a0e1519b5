#include "terratraj/apps/demo_command.hpp"

#include <fstream>
#include <ostream>

#include "terratraj/apps/output_paths.hpp"
#include "terratraj/apps/plan_command.hpp"
#include "terratraj/apps/terrain_commands.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"

namespace terratraj::apps {
namespace {

constexpr double kPlanTimeLimitS = 1.0;     // TAEASL's budget [s]
constexpr double kRefineTimeLimitS = 30.0;  // per candidate [s]

}  // namespace

ProblemSpec demoProblem(const terrain::GeneratorOptions& generator) {
  ProblemSpec problem;
  problem.source_file = "demo";
  problem.terrain.generate = generator;
  problem.vehicle.model = VehicleModelKind::kPoint;
  problem.vehicle.limits.pitch_max = problem.vehicle.limits.roll_max = 25.0 * kRadiansPerDegree;
  terrain::GridGeometry geometry;
  geometry.rows = generator.rows;
  geometry.cols = generator.cols;
  geometry.cell = generator.cell;
  const auto [start, goal] = terrain::standardStartGoal(geometry);
  problem.start.x = start.x();
  problem.start.y = start.y();
  problem.goal.x = goal.x();
  problem.goal.y = goal.y();
  problem.planner.kind = PlannerKind::kTaeasl;
  problem.planner.time_limit_s = kPlanTimeLimitS;
  problem.planner.homotopy_classes = 3;
  problem.refine.time_limit_s = kRefineTimeLimitS;
  return problem;
}

int runDemo(const DemoOptions& options, CommandContext& context) {
  std::error_code error;
  std::filesystem::create_directories(options.out_dir, error);
  if (error) {
    throw InputError("--out-dir: cannot create '" + options.out_dir.string() +
                     "': " + error.message());
  }
  context.log->info("demo: generating '{}' terrain, {} x {} cells of {} m, seed {}",
                    terrain::terrainKindName(options.generator.kind), options.generator.cols,
                    options.generator.rows, options.generator.cell, options.generator.seed);
  const terrain::ElevationMap map = terrain::generateTerrain(options.generator);
  const std::filesystem::path tif = options.out_dir / "terrain.tif";
  terrain::saveGeoTiff(map, tif);
  const terrain::TerrainStatistics stats = terrain::computeTerrainStatistics(map);

  ProblemSpec problem = demoProblem(options.generator);
  PlanOptions plan;
  plan.out_dir = options.out_dir;
  plan.refine = true;
  if (options.plot) plan.plot = options.out_dir / "plot.png";
  const PlanRun run = executePlan(problem, plan, context);

  nlohmann::json report = run.report;
  report["terrain"] = {{"kind", terrain::terrainKindName(options.generator.kind)},
                       {"seed", options.generator.seed},
                       {"file", tif.string()},
                       {"statistics", terrainStatisticsJson(stats)}};
  report["problem"] = {
      {"vehicle", vehicleModelName(problem.vehicle.model)},
      {"start", {problem.start.x, problem.start.y, problem.start.heading}},
      {"goal", {problem.goal.x, problem.goal.y, problem.goal.heading}},
      {"cost", costKindName(problem.cost.kind)},
  };
  const std::filesystem::path report_file = options.out_dir / "report.json";
  report["report"] = report_file.string();
  writeJsonFile(report, report_file);
  context.log->info("demo: wrote {}", report_file.string());
  if (context.json) {
    context.out << report.dump(2) << '\n';
    return run.exit_status;
  }
  context.out << "terratraj demo: a " << map.geometry().width() << " m x "
              << map.geometry().height() << " m '"
              << terrain::terrainKindName(options.generator.kind) << "' terrain (seed "
              << options.generator.seed << "), point vehicle from (" << problem.start.x << ", "
              << problem.start.y << ") to (" << problem.goal.x << ", " << problem.goal.y
              << "), minimum time.\n"
              << "TAEASL (1 s) found routes in distinct homotopy classes; each was refined:\n"
              << run.summary << "files in " << options.out_dir.string()
              << "/: terrain.tif, report.json, solution_<k>.csv, refined_<k>.csv";
  if (report.contains("plots") && report["plots"]["status"] == "ok") {
    context.out << ", plot.png, plot-profiles.png, plot-convergence.png";
  }
  context.out << '\n';
  return run.exit_status;
}

}  // namespace terratraj::apps
