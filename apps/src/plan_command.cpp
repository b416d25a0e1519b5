#include "terratraj/apps/plan_command.hpp"

#include <algorithm>
#include <chrono>
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
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/primitive_file.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {
namespace {

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
                     ": start.omega: the planners cannot turn in place: omega must be 0 when "
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
  const auto fileAt = [&info](std::size_t k) {
    return k < info.files.size() ? nlohmann::json(info.files[k].string()) : nlohmann::json(nullptr);
  };
  const auto checkJson = [&info](std::size_t k) {
    if (k >= info.checks.size()) return nlohmann::json(nullptr);
    nlohmann::json violated = nlohmann::json::array();
    for (const search::CheckViolation& v : info.checks[k].violations) violated.push_back(v.limit);
    return nlohmann::json{{"ok", info.checks[k].ok()},
                          {"constraint_violation", info.checks[k].max_violation},
                          {"violated_limits", violated}};
  };
  nlohmann::json solutions = nlohmann::json::array();
  if (result.status == search::PlanStatus::kSolved && result.solutions.empty()) {
    solutions.push_back({{"cost_s", number(result.best_cost_s)},
                         {"length_m", number(result.length_m)},
                         {"homotopy", ""},
                         {"file", fileAt(0)},
                         {"check", checkJson(0)}});
  }
  for (std::size_t k = 0; k < result.solutions.size(); ++k) {
    const search::PlanSolution& s = result.solutions[k];
    solutions.push_back({{"cost_s", number(s.cost_s)},
                         {"length_m", number(s.length_m)},
                         {"homotopy", s.homotopy},
                         {"file", fileAt(k)},
                         {"search_cost_s", number(s.search_cost_s)},
                         {"proven_optimal", s.proven_optimal},
                         {"found_ms", s.found_ms},
                         {"check", checkJson(k)}});
  }
  const search::PlanStatistics& st = result.statistics;
  nlohmann::json statistics{{"iterations", st.iterations},
                            {"attempts", st.attempts},
                            {"trapped", st.trapped},
                            {"pruned", st.pruned},
                            {"goal_attempts", st.goal_attempts},
                            {"goal_connections", st.goal_connections},
                            {"improvements", st.improvements},
                            {"pruned_nodes", st.pruned_nodes}};
  if (info.planner != "prm") {
    const search::SearchStatistics& ss = result.search;
    statistics = {{"expansions", ss.expansions},
                  {"generated", ss.generated},
                  {"edge_evaluations", ss.edge_evaluations},
                  {"invalid_edges", ss.invalid_edges},
                  {"cache_hits", ss.cache_hits},
                  {"rounds", ss.rounds},
                  {"final_epsilon", ss.final_epsilon},
                  {"homotopy_classes", ss.homotopy_classes},
                  {"frames", ss.frames},
                  {"pruned_signatures", ss.pruned_signatures}};
  }
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
      {"statistics", statistics},
      {"cost_history", history},
  };
  if (!info.checks.empty()) {
    double worst = 0.0;
    nlohmann::json violated = nlohmann::json::array();
    for (const search::CheckReport& check : info.checks) {
      worst = std::max(worst, check.max_violation);
      for (const search::CheckViolation& v : check.violations) {
        if (std::find(violated.begin(), violated.end(), v.limit) == violated.end()) {
          violated.push_back(v.limit);
        }
      }
    }
    json["constraint_violation"] = worst;
    json["violated_limits"] = violated;
  }
  for (const auto& [key, value] : info.extra.items()) json[key] = value;
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
    info.files.push_back(csv);
    info.checks.push_back(search::TrajectoryChecker(problem).check(result.trajectory));
  }
  return planReportJson(result, info);
}

namespace {

// The lattice spacing: the problem's, else the multiple of the map cell nearest 0.5 m.
double latticeResolution(const ProblemSpec& problem, const terrain::GridGeometry& geometry) {
  if (problem.planner.lattice_resolution_m) return *problem.planner.lattice_resolution_m;
  return geometry.cell * std::max(1.0, std::round(0.5 / geometry.cell));
}

// Fails with the key at fault when no lattice state can lie in the goal region.
void checkGoalReachable(const ProblemSpec& problem, const search::LatticeGraph& graph) {
  const search::GoalRegion& goal = graph.problem().goal;
  const search::LatticeSpec& lattice = graph.lattice();
  const Eigen::Vector2d cells =
      (goal.position - graph.problem().start.position) / lattice.resolution;
  const search::LatticeState nearest{static_cast<int>(std::lround(cells.x())),
                                     static_cast<int>(std::lround(cells.y())), 0};
  if ((graph.position(nearest) - goal.position).norm() > goal.position_tolerance) {
    throw InputError(problem.source_file.string() + ": planner.goal_position_tolerance_m: " +
                     formatNumber(goal.position_tolerance) +
                     " m holds no lattice position (spacing " + formatNumber(lattice.resolution) +
                     " m from the start): use at least " +
                     formatNumber(std::ceil(lattice.resolution * 0.7072 * 100.0) / 100.0) + " m");
  }
  const double heading_gap = std::abs(
      search::wrapAngle(goal.heading - lattice.headingAngle(lattice.nearestHeading(goal.heading))));
  if (heading_gap > goal.heading_tolerance) {
    throw InputError(problem.source_file.string() +
                     ": planner.goal_heading_tolerance: " + formatNumber(goal.heading_tolerance) +
                     " rad holds no lattice heading (" + std::to_string(lattice.heading_count) +
                     " headings): use at least " + formatNumber(heading_gap) + " rad");
  }
}

// Writes every solution, re-checks it independently and fills the report's info.
void writeSolutions(const search::PlanResult& result, const search::PlanningProblem& query,
                    const std::filesystem::path& out_dir, PlanReportInfo& info,
                    CommandContext& context) {
  if (result.status != search::PlanStatus::kSolved) return;
  createDirectories(out_dir);
  const auto write = [&](const models::Trajectory& trajectory, std::size_t k) {
    const std::filesystem::path file = out_dir / ("solution_" + std::to_string(k) + ".csv");
    models::writeTrajectoryCsv(trajectory, file);
    info.files.push_back(file);
    info.checks.push_back(search::TrajectoryChecker(query).check(trajectory));
    if (!info.checks.back().ok()) {
      context.log->warn("the re-check of solution {} found violations:\n{}", k,
                        info.checks.back().summary());
    }
  };
  if (result.solutions.empty()) {
    write(result.trajectory, 0);
  } else {
    for (std::size_t k = 0; k < result.solutions.size(); ++k) {
      write(result.solutions[k].trajectory, k);
    }
  }
}

search::FrameAnchor parseAnchor(const std::string& name) {
  if (name == "start") return search::FrameAnchor::kStart;
  if (name == "midpoint") return search::FrameAnchor::kMidpoint;
  return search::FrameAnchor::kMapCenter;
}

// The lattice planners: primitives (file, cache or generated), graph, A* / ARA* or TAEASL.
search::PlanResult runLatticePlanner(const ProblemSpec& problem,
                                     const search::PlanningProblem& query, PlanReportInfo& info,
                                     CommandContext& context) {
  search::LatticeSpec lattice;
  lattice.resolution = latticeResolution(problem, query.map->geometry());
  lattice.heading_count = problem.planner.heading_count;
  search::PrimitiveGenerationOptions generation;
  if (problem.planner.primitive_speed) generation.speed = *problem.planner.primitive_speed;
  const auto load_started = std::chrono::steady_clock::now();
  const search::LoadedPrimitives primitives = search::loadOrGeneratePrimitives(
      lattice, query.limits, generation,
      problem.planner.primitives ? *problem.planner.primitives : std::filesystem::path());
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_started)
          .count();
  if (!primitives.cache_note.empty()) context.log->info("primitives: {}", primitives.cache_note);
  context.log->info("{} motion primitives ({}{}{}), {} ms", primitives.set.size(),
                    search::primitiveSourceName(primitives.source),
                    primitives.path.empty() ? "" : " ", primitives.path.string(), load_ms);

  search::LatticeGraphOptions graph_options;
  if (problem.cost.kind == CostKind::kSlopeDwell) {
    graph_options.slope_dwell_alpha = problem.cost.alpha;
  }
  const search::LatticeGraph graph(query, primitives.set, graph_options);
  if (graph.error()) throw InputError(problem.source_file.string() + ": " + *graph.error());
  checkGoalReachable(problem, graph);
  info.extra["lattice"] = {
      {"resolution_m", lattice.resolution},
      {"heading_count", lattice.heading_count},
      {"sample_spacing_m", graph.sampleSpacing()},
      {"start_connectors", graph.connectorCount()},
      {"primitives",
       {{"count", primitives.set.size()},
        {"source", search::primitiveSourceName(primitives.source)},
        {"file", primitives.path.empty() ? nlohmann::json(nullptr)
                                         : nlohmann::json(primitives.path.string())},
        {"generation_speed", primitives.set.generation.speed},
        {"load_ms", load_ms}}}};

  const search::TerminationCondition termination =
      search::TerminationCondition::timeLimit(problem.planner.time_limit_s);
  if (problem.planner.kind == PlannerKind::kLattice) {
    search::LatticePlannerOptions options;
    options.algorithm = problem.planner.algorithm == "astar" ? search::LatticeAlgorithm::kAStar
                                                             : search::LatticeAlgorithm::kAraStar;
    options.initial_epsilon = problem.planner.initial_epsilon;
    options.epsilon_step = problem.planner.epsilon_step;
    info.extra["lattice"]["algorithm"] = search::latticeAlgorithmName(options.algorithm);
    info.extra["lattice"]["initial_epsilon"] = options.initial_epsilon;
    info.extra["lattice"]["epsilon_step"] = options.epsilon_step;
    context.log->info("planning with the lattice ({}) for {} s", problem.planner.algorithm,
                      problem.planner.time_limit_s);
    return search::LatticePlanner(graph, options).solve(termination);
  }
  search::TaeaslOptions options;
  options.homotopy_classes = problem.planner.homotopy_classes;
  options.frame_radius = problem.planner.frame_radius_m;
  options.anchor = parseAnchor(problem.planner.frame_anchor);
  options.heuristic_weight = problem.planner.heuristic_weight;
  if (problem.planner.max_signature_length) {
    options.max_signature_length = *problem.planner.max_signature_length;
  }
  const search::TaeaslPlanner planner(graph, options);
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t k = 0; k < planner.frames().size(); ++k) {
    const search::ReferenceFrame& f = planner.frames().frames()[k];
    frames.push_back({{"name", search::HomotopySignature::frameName(static_cast<int>(k))},
                      {"cluster", f.cluster},
                      {"start", {f.start.x(), f.start.y()}},
                      {"end", {f.end.x(), f.end.y()}}});
  }
  info.extra["taeasl"] = {{"homotopy_classes", options.homotopy_classes},
                          {"frame_radius_m", options.frame_radius},
                          {"frame_anchor", search::frameAnchorName(options.anchor)},
                          {"anchor", {planner.anchorPosition().x(), planner.anchorPosition().y()}},
                          {"heuristic_weight", options.heuristic_weight},
                          {"max_signature_length", planner.maxSignatureLength()},
                          {"frames", frames}};
  context.log->info("planning with TAEASL for {} s ({} reference frames)",
                    problem.planner.time_limit_s, planner.frames().size());
  return planner.solve(termination);
}

}  // namespace

int runPlan(const PlanOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  if (options.planner) {
    const std::optional<PlannerKind> kind = parsePlannerKind(*options.planner);
    if (!kind) throw InputError("--planner: unknown planner '" + *options.planner + "'");
    problem.planner.kind = *kind;
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

  PlanReportInfo info;
  info.planner = plannerKindName(problem.planner.kind);
  info.time_limit_s = problem.planner.time_limit_s;
  info.seed = problem.planner.seed;
  search::PlanResult result;
  if (problem.planner.kind == PlannerKind::kPrm) {
    search::PrmOptions prm;
    prm.seed = problem.planner.seed;
    search::KinodynamicPrm planner(query, prm);
    context.log->info("planning with prm for {} s (seed {}, {} model)",
                      problem.planner.time_limit_s, prm.seed, vehicle.name());
    result = planner.solve(search::TerminationCondition::timeLimit(problem.planner.time_limit_s));
  } else {
    result = runLatticePlanner(problem, query, info, context);
  }
  writeSolutions(result, query, options.out_dir, info, context);

  const nlohmann::json report = planReportJson(result, info);
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << search::planStatusName(result.status) << " (" << info.planner << ", "
                << result.planning_time_ms << " ms, " << result.nodes << " nodes)";
    if (!result.reason.empty()) context.out << ": " << result.reason;
    context.out << '\n';
    if (result.status == search::PlanStatus::kSolved) {
      context.out << "  first solution  " << *result.first_solution_ms << " ms, cost "
                  << result.first_solution_cost_s << " s\n";
      for (std::size_t k = 0; k < info.files.size(); ++k) {
        const bool has = k < result.solutions.size();
        const double cost = has ? result.solutions[k].cost_s : result.best_cost_s;
        const double length = has ? result.solutions[k].length_m : result.length_m;
        context.out << "  solution " << k << "      cost " << cost << " s, length " << length
                    << " m";
        if (has && !result.solutions[k].homotopy.empty()) {
          context.out << ", class " << result.solutions[k].homotopy;
        }
        context.out << ", re-check " << (info.checks[k].ok() ? "ok" : "VIOLATED") << ", "
                    << info.files[k].string() << '\n';
      }
    }
  }
  return result.status == search::PlanStatus::kSolved ? kExitSuccess : kExitNotSolved;
}

int runPrimitives(const PrimitivesOptions& options, CommandContext& context) {
  const ProblemSpec problem = loadProblem(options.problem);
  const terrain::ElevationMap map = terrain::loadTerrain(problem.terrain);
  search::LatticeSpec lattice;
  lattice.resolution = latticeResolution(problem, map.geometry());
  lattice.heading_count = problem.planner.heading_count;
  search::PrimitiveGenerationOptions generation;
  if (problem.planner.primitive_speed) generation.speed = *problem.planner.primitive_speed;
  context.log->info("generating motion primitives: {} m lattice, {} headings", lattice.resolution,
                    lattice.heading_count);
  const search::PrimitiveGenerationResult result =
      search::generatePrimitives(lattice, problem.vehicle.limits, generation);
  if (const std::optional<std::string> error =
          result.set.checkAgainst(lattice, &problem.vehicle.limits)) {
    std::string message = "motion primitives: generation failed: " + *error;
    for (const std::string& f : result.failures) message += "; " + f;
    throw InputError(message);
  }
  search::writePrimitiveFile(result.set, options.out);
  const search::PrimitiveGenerationInfo& g = result.set.generation;
  nlohmann::json failures = nlohmann::json::array();
  for (const std::string& f : result.failures) failures.push_back(f);
  const nlohmann::json report{{"status", "ok"},
                              {"file", options.out.string()},
                              {"resolution_m", lattice.resolution},
                              {"heading_count", lattice.heading_count},
                              {"primitives", result.set.size()},
                              {"generation_speed", g.speed},
                              {"solves", g.solves},
                              {"failed_solves", g.failures},
                              {"generation_time_ms", g.generation_time_ms},
                              {"missing", failures}};
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << result.set.size() << " primitives (" << g.solves << " solves, " << g.failures
                << " failed) in " << g.generation_time_ms << " ms -> " << options.out.string()
                << '\n';
    for (const std::string& f : result.failures) context.out << "  missing: " << f << '\n';
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
