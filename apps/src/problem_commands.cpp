#include "terratraj/apps/problem_commands.hpp"

#include <ostream>
#include <sstream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/plan_command.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/apps/problem_translation.hpp"
#include "terratraj/apps/refine_command.hpp"
#include "terratraj/apps/solve_command.hpp"
#include "terratraj/apps/terrain_commands.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_source.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"

namespace terratraj::apps {
namespace {

nlohmann::json stateJson(const BoundaryState& state) {
  return {{"x", state.x},
          {"y", state.y},
          {"heading", state.heading},
          {"v", state.v},
          {"omega", state.omega}};
}

nlohmann::json optionalPath(const std::optional<std::filesystem::path>& path) {
  return path ? nlohmann::json(path->string()) : nlohmann::json(nullptr);
}

nlohmann::json terrainSourceJson(const terrain::TerrainSource& source) {
  nlohmann::json json{
      {"file", optionalPath(source.file)},
      {"z_scale", source.raster.z_scale},
      {"frame", source.frame == terrain::CoordinateFrame::kWorld ? "world" : "local"},
      {"interpolation", terrain::interpolationName(source.interpolation)},
      {"obstacles",
       {{"file", optionalPath(source.obstacles.file)},
        {"max_slope", source.obstacles.max_slope ? nlohmann::json(*source.obstacles.max_slope)
                                                 : nlohmann::json(nullptr)}}},
  };
  json["cell"] = source.raster.cell ? nlohmann::json(*source.raster.cell) : nlohmann::json(nullptr);
  if (source.generate) {
    const terrain::GeneratorOptions& g = *source.generate;
    json["generate"] = {{"kind", terrain::terrainKindName(g.kind)},
                        {"rows", g.rows},
                        {"cols", g.cols},
                        {"cell", g.cell},
                        {"seed", g.seed}};
  } else {
    json["generate"] = nullptr;
  }
  return json;
}

constexpr double kDegreesPerRadian = 57.29577951308232;

}  // namespace

models::AttitudeResult restingAttitude(const models::TerrainFollowingModel& model,
                                       const BoundaryState& state, const char* which,
                                       const ProblemSpec& problem) {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  const models::AttitudeStatus status =
      model.compute({state.x, state.y, state.heading}, workspace, result);
  if (status != models::AttitudeStatus::kOk) {
    std::ostringstream message;
    message << problem.source_file.string() << ": " << which << ": the "
            << models::vehicleModelName(problem.vehicle.model)
            << " vehicle cannot rest on the terrain at (" << state.x << ", " << state.y
            << ") m, heading " << state.heading << " rad ("
            << (status == models::AttitudeStatus::kNoTerrain
                    ? "a wheel is off the map or over no-data cells"
                    : "no suspension configuration touches the ground")
            << ")";
    throw InputError(message.str());
  }
  return result;
}

namespace {

nlohmann::json attitudeJson(const models::AttitudeResult& result) {
  return {
      {"z", result.attitude.z}, {"roll", result.attitude.roll}, {"pitch", result.attitude.pitch}};
}

// Reads the problem's look-up tables, so that a bad table is reported now.

}  // namespace

nlohmann::json problemJson(const ProblemSpec& problem, const ProblemScene& scene) {
  const VehicleLimits& l = problem.vehicle.limits;
  return {
      {"file", problem.source_file.string()},
      {"terrain", terrainSourceJson(problem.terrain)},
      {"vehicle",
       {{"model", vehicleModelName(problem.vehicle.model)},
        {"limits",
         {{"v_max", l.v_max},
          {"a_max", l.a_max},
          {"omega_max", l.omega_max},
          {"kappa_max", l.kappa_max},
          {"sigma_max", l.sigma_max},
          {"pitch_max", l.pitch_max},
          {"roll_max", l.roll_max}}},
        {"tables",
         {{"pitch", optionalPath(problem.vehicle.tables.pitch)},
          {"roll_curvature", optionalPath(problem.vehicle.tables.roll_curvature)}}}}},
      {"start", stateJson(scene.start())},
      {"goal", stateJson(scene.goal())},
      {"pose_frame", "local"},  // start and goal as resolved on the map
      {"cost", {{"kind", costKindName(problem.cost.kind)}, {"alpha", problem.cost.alpha}}},
      {"solver",
       {{"method", solverMethodName(problem.solver.method)},
        {"intervals", problem.solver.intervals ? nlohmann::json(*problem.solver.intervals)
                                               : nlohmann::json("auto")},
        {"initial_guess",
         problem.solver.initial_guess == InitialGuessKind::kFlat ? "flat" : "auto"},
        {"max_iterations", problem.solver.max_iterations},
        {"tolerance",
         {{"position_m", problem.solver.tolerance_position_m},
          {"heading_rad", problem.solver.tolerance_heading_rad}}},
        {"time_limit_s", problem.solver.time_limit_s ? nlohmann::json(*problem.solver.time_limit_s)
                                                     : nlohmann::json(nullptr)},
        // The search seed's PRM budget (at most half the time left when a limit is set).
        {"search_time_s", searchSeedTime(problem)}}},
      {"planner",
       {{"kind", plannerKindName(problem.planner.kind)},
        {"time_limit_s", planningTimeLimit(problem)},
        {"seed", problem.planner.seed},
        {"homotopy_classes", problem.planner.homotopy_classes},
        {"frame_radius_m", problem.planner.frame_radius_m},
        {"goal_position_tolerance_m", goalPositionTolerance(problem, scene.map().geometry())},
        {"goal_heading_tolerance_rad", problem.planner.goal_heading_tolerance},
        {"goal_speed_tolerance", problem.planner.goal_speed_tolerance}}},
  };
}

void checkForEveryCommand(const ProblemSpec& problem, const ProblemScene& scene) {
  // A failure names the commands that would refuse the file.
  const auto as = [&](const char* commands, const auto& check) {
    try {
      check();
    } catch (const InputError& error) {
      throw InputError(std::string(error.what()) + " [refused by " + commands + "]");
    }
  };
  as("solve", [&] {
    if (isTranscriptionMethod(problem.solver.method)) (void)transcriptionOptions(problem);
  });
  as("plan and refine", [&] { (void)planningProblem(problem, scene); });
  if (problem.planner.kind != PlannerKind::kPrm) {
    as("plan", [&] { checkLatticeGoal(problem, planningProblem(problem, scene)); });
  }
  as("refine and plan --refine", [&] { (void)refinementOptions(problem, std::nullopt); });
}

int runCheck(const CheckOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  context.log->info("{}: problem read", options.problem.string());
  const ProblemScene scene(problem, context);
  checkForEveryCommand(problem, scene);
  const terrain::ElevationMap& map = scene.map();
  const models::AttitudeResult& start = scene.startAttitude();
  const models::AttitudeResult& goal = scene.goalAttitude();
  const terrain::TerrainStatistics stats = terrain::computeTerrainStatistics(map);
  if (context.json) {
    nlohmann::json json{{"status", "ok"},
                        {"problem", problemJson(problem, scene)},
                        {"start_attitude", attitudeJson(start)},
                        {"goal_attitude", attitudeJson(goal)},
                        {"terrain", terrainStatisticsJson(stats)}};
    context.out << json.dump(2) << '\n';
  } else {
    context.out << options.problem.string() << ": ok\n"
                << "  vehicle    " << vehicleModelName(problem.vehicle.model) << ", v_max "
                << problem.vehicle.limits.v_max << " m/s\n"
                << "  start      (" << scene.start().x << ", " << scene.start().y << ") m, heading "
                << scene.start().heading << " rad (local frame); pitch "
                << start.attitude.pitch * kDegreesPerRadian << " deg, roll "
                << start.attitude.roll * kDegreesPerRadian << " deg\n"
                << "  goal       (" << scene.goal().x << ", " << scene.goal().y << ") m, heading "
                << scene.goal().heading << " rad (local frame); pitch "
                << goal.attitude.pitch * kDegreesPerRadian << " deg, roll "
                << goal.attitude.roll * kDegreesPerRadian << " deg\n"
                << "  cost       " << costKindName(problem.cost.kind) << ", solver "
                << solverMethodName(problem.solver.method) << ", planner "
                << plannerKindName(problem.planner.kind) << '\n'
                << "terrain\n"
                << terrainStatisticsText(stats);
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
