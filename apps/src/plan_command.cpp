#include "terratraj/apps/plan_command.hpp"

#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/apps/vehicle_factory.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {
namespace {

constexpr const char* kSolutionFile = "solution_0.csv";

// JSON has no NaN or infinity: such values are null.
nlohmann::json number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string formatNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void createDirectories(const std::filesystem::path& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    throw InputError("--out-dir: cannot create '" + dir.string() + "': " + error.message());
  }
}

// The planner's view of the problem file's start and goal.
search::PlannerState startState(const ProblemSpec& problem) {
  const BoundaryState& s = problem.start;
  if (s.v == 0.0 && s.omega != 0.0) {
    throw InputError(problem.source_file.string() +
                     ": start.omega: the prm planner cannot turn in place: omega must be 0 when "
                     "v = 0 (got " +
                     formatNumber(s.omega) + " rad/s)");
  }
  search::PlannerState state;
  state.position = {s.x, s.y};
  state.heading = s.heading;
  state.v = s.v;
  state.curvature = s.v > 0.0 ? s.omega / s.v : 0.0;
  return state;
}

search::GoalRegion goalRegion(const ProblemSpec& problem) {
  search::GoalRegion goal;
  goal.position = {problem.goal.x, problem.goal.y};
  goal.heading = problem.goal.heading;
  goal.v = problem.goal.v;
  goal.position_tolerance = problem.planner.goal_position_tolerance_m;
  goal.heading_tolerance = problem.planner.goal_heading_tolerance;
  goal.speed_tolerance = problem.planner.goal_speed_tolerance;
  return goal;
}

}  // namespace

nlohmann::json planReportJson(const search::PlanResult& result, const PlanReportInfo& info) {
  nlohmann::json history = nlohmann::json::array();
  for (const search::CostSample& sample : result.cost_history) {
    history.push_back({{"time_ms", sample.time_ms}, {"cost_s", sample.cost_s}});
  }
  nlohmann::json solutions = nlohmann::json::array();
  if (result.status == search::PlanStatus::kSolved) {
    solutions.push_back(
        {{"cost_s", number(result.best_cost_s)},
         {"length_m", number(result.length_m)},
         {"homotopy", ""},
         {"file", info.file ? nlohmann::json(info.file->string()) : nlohmann::json(nullptr)}});
  }
  const search::PlanStatistics& st = result.statistics;
  nlohmann::json json{
      {"status", search::planStatusName(result.status)},
      {"planner", info.planner},
      {"time_limit_s", info.time_limit_s},
      {"first_solution_ms", result.first_solution_ms ? nlohmann::json(*result.first_solution_ms)
                                                     : nlohmann::json(nullptr)},
      {"planning_time_ms", result.planning_time_ms},
      {"nodes", result.nodes},
      {"trapped_fraction", result.trappedFraction()},
      {"solutions", solutions},
      {"seed", info.seed},
      {"reason", result.reason},
      {"best_cost_s", number(result.best_cost_s)},
      {"first_solution_cost_s", number(result.first_solution_cost_s)},
      {"statistics",
       {{"iterations", st.iterations},
        {"attempts", st.attempts},
        {"trapped", st.trapped},
        {"pruned", st.pruned},
        {"goal_attempts", st.goal_attempts},
        {"goal_connections", st.goal_connections},
        {"improvements", st.improvements},
        {"pruned_nodes", st.pruned_nodes}}},
      {"cost_history", history},
  };
  if (info.check) {
    nlohmann::json violated = nlohmann::json::array();
    for (const search::CheckViolation& v : info.check->violations) violated.push_back(v.limit);
    json["constraint_violation"] = info.check->max_violation;
    json["violated_limits"] = violated;
  }
  return json;
}

nlohmann::json planDemoProblem(const terrain::ElevationMap& map, const std::filesystem::path& csv,
                               double time_limit_s, CommandContext& context) {
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const std::unique_ptr<models::TerrainFollowingModel> vehicle =
      makeTerrainFollowingModel(VehicleModelKind::kPoint, surface);
  search::PlanningProblem problem(map, *vehicle);
  const auto [start, goal] = terrain::standardStartGoal(map.geometry());
  problem.start.position = start;
  problem.goal.position = goal;
  problem.limits.pitch_max = problem.limits.roll_max = 0.5;
  PlanReportInfo info;
  info.time_limit_s = time_limit_s;
  if (const std::optional<std::string> error = problem.validate()) {
    nlohmann::json report{{"status", "error"}, {"error", "demo plan: " + *error}};
    return report;
  }
  context.log->info("demo: planning with the kinodynamic PRM for {} s (point vehicle)",
                    time_limit_s);
  search::KinodynamicPrm planner(problem);
  const search::PlanResult result =
      planner.solve(search::TerminationCondition::timeLimit(time_limit_s));
  if (result.status == search::PlanStatus::kSolved) {
    models::writeTrajectoryCsv(result.trajectory, csv);
    info.file = csv;
    info.check = search::TrajectoryChecker(problem).check(result.trajectory);
  }
  return planReportJson(result, info);
}

int runPlan(const PlanOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  if (options.planner) {
    const std::optional<PlannerKind> kind = parsePlannerKind(*options.planner);
    if (!kind) throw InputError("--planner: unknown planner '" + *options.planner + "'");
    problem.planner.kind = *kind;
  }
  if (problem.planner.kind != PlannerKind::kPrm) {
    throw InputError(std::string("planner '") + plannerKindName(problem.planner.kind) +
                     "' is not implemented yet: only 'prm' is available (--planner prm)");
  }
  if (options.time_limit_s) {
    if (!std::isfinite(*options.time_limit_s) || *options.time_limit_s < 0.0) {
      throw InputError("--time-limit: must be a finite number >= 0 s (got " +
                       formatNumber(*options.time_limit_s) + ")");
    }
    problem.planner.time_limit_s = *options.time_limit_s;
  }
  if (options.seed) problem.planner.seed = *options.seed;

  const ProblemScene scene(problem, context);
  const terrain::ElevationMap& map = scene.map();
  const models::TerrainFollowingModel& vehicle = scene.vehicle();

  search::PlanningProblem query(map, vehicle);
  query.limits = problem.vehicle.limits;
  query.start = startState(problem);
  query.goal = goalRegion(problem);
  query.pitch_table = scene.pitchTable();
  query.roll_curvature_table = scene.rollCurvatureTable();
  if (const std::optional<std::string> error = query.validate()) {
    throw InputError(problem.source_file.string() + ": " + *error);
  }

  search::PrmOptions prm;
  prm.seed = problem.planner.seed;
  search::KinodynamicPrm planner(query, prm);
  context.log->info("planning with prm for {} s (seed {}, {} model)", problem.planner.time_limit_s,
                    prm.seed, vehicle.name());
  const search::PlanResult result =
      planner.solve(search::TerminationCondition::timeLimit(problem.planner.time_limit_s));

  PlanReportInfo info;
  info.planner = plannerKindName(problem.planner.kind);
  info.time_limit_s = problem.planner.time_limit_s;
  info.seed = problem.planner.seed;
  if (result.status == search::PlanStatus::kSolved) {
    createDirectories(options.out_dir);
    const std::filesystem::path file = options.out_dir / kSolutionFile;
    models::writeTrajectoryCsv(result.trajectory, file);
    info.file = file;
    info.check = search::TrajectoryChecker(query).check(result.trajectory);
    if (!info.check->ok()) {
      context.log->warn("the re-check of the trajectory found violations:\n{}",
                        info.check->summary());
    }
  }
  const nlohmann::json report = planReportJson(result, info);
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << search::planStatusName(result.status) << " (prm, " << result.planning_time_ms
                << " ms, " << result.nodes << " nodes, trapped fraction "
                << result.trappedFraction() << ")";
    if (!result.reason.empty()) context.out << ": " << result.reason;
    context.out << '\n';
    if (result.status == search::PlanStatus::kSolved) {
      context.out << "  first solution  " << *result.first_solution_ms << " ms, cost "
                  << result.first_solution_cost_s << " s\n"
                  << "  best cost       " << result.best_cost_s << " s, length " << result.length_m
                  << " m (" << result.cost_history.size() << " improvements)\n"
                  << "  re-check        " << (info.check->ok() ? "all limits hold" : "VIOLATED")
                  << '\n'
                  << "  trajectory      " << info.file->string() << '\n';
    }
  }
  return result.status == search::PlanStatus::kSolved ? kExitSuccess : kExitNotSolved;
}

}  // namespace terratraj::apps
