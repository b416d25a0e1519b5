#include "terratraj/apps/problem_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <locale>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "terratraj/terrain/grid_geometry.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "yaml_reader.hpp"

namespace terratraj::apps {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
constexpr double kRightAngleDeg = 90.0;  // upper bound (open) of pitch, roll, slope limits
constexpr double kMinSpeedLimit = 0.01;  // vehicle.limits.v_max [m/s]
constexpr double kMaxSpeedLimit = 50.0;
constexpr int kMinGridSide = 2;        // generate.rows / cols
constexpr int kMinIntervals = 2;       // solver.intervals
constexpr int kMaxIntervals = 100000;  // keeps allocations sane
constexpr int kMinIterations = 1;      // solver.max_iterations
constexpr int kMaxIterations = 1000000;
constexpr int kMaxSearchMilestones = 100000000;  // solver.search_improve_milestones
constexpr int kMaxSearchImprovements = 1000;     // solver.search_improvements
constexpr int kMinHomotopyClasses = 1;           // planner.homotopy_classes
constexpr int kMaxHomotopyClasses = 1000;
constexpr std::size_t kMaxProblemFileBytes = std::size_t{16} << 20;  // 16 MiB
constexpr std::size_t kReadChunkBytes = std::size_t{1} << 16;

using namespace yaml_reader;  // NOLINT: the reader's vocabulary

// Wraps an angle [rad] to (-pi, pi].
double wrapAngle(double angle) {
  double wrapped = std::remainder(angle, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

// ------------------------------------------------------------------------------------------
// Sections.

// (0, 90) deg: pitch, roll and slope limits.
Range rightAngleRangeDeg() { return Range::openInterval(0.0, kRightAngleDeg, "deg"); }

// `terrain.generate`; missing keys keep GeneratorOptions' defaults.
terrain::GeneratorOptions parseGenerate(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field, {"kind", "rows", "cols", "cell", "seed"});
  terrain::GeneratorOptions options;
  options.kind = readEnum<terrain::TerrainKind>(ctx, map.require("kind"), terrain::parseTerrainKind,
                                                terrain::terrainKindNames());
  map.readIntInto("rows", kMinGridSide, std::numeric_limits<int>::max(), options.rows);
  map.readIntInto("cols", kMinGridSide, std::numeric_limits<int>::max(), options.cols);
  map.readNumberInto("cell", Range::positive(), options.cell);
  map.readSeedInto("seed", options.seed);
  const std::int64_t cells = std::int64_t{options.rows} * std::int64_t{options.cols};
  if (cells > terrain::kMaxGeneratedCells) {
    map.fail("", "rows * cols = " + std::to_string(options.rows) + " * " +
                     std::to_string(options.cols) + " cells exceeds the limit of " +
                     std::to_string(terrain::kMaxGeneratedCells));
  }
  return options;
}

// `terrain.obstacles`: a lethal raster and/or a maximum slope, at least one.
terrain::ObstacleSource parseObstacles(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field, {"file", "band", "max_slope", "max_slope_deg"});
  terrain::ObstacleSource obstacles;
  if (const std::optional<Field> file = map.find("file")) obstacles.file = readPath(ctx, *file);
  if (map.find("band")) {
    int band = 1;
    map.readIntInto("band", 1, 65535, band);
    obstacles.band = band;
  }
  obstacles.max_slope = map.optionalAngle("max_slope", rightAngleRangeDeg());
  if (!obstacles.file && !obstacles.max_slope && !obstacles.band) {
    map.fail("", "give file, band and/or max_slope_deg (or remove obstacles)");
  }
  return obstacles;
}

// `terrain.frame` names.
std::optional<terrain::CoordinateFrame> parseFrame(std::string_view name) {
  if (name == "local") return terrain::CoordinateFrame::kLocal;
  if (name == "world") return terrain::CoordinateFrame::kWorld;
  return std::nullopt;
}

// `terrain.interpolation` names: the surfaces smooth enough to optimise on (C1 or better).
std::optional<terrain::Interpolation> parseSmoothInterpolation(std::string_view name) {
  const std::optional<terrain::Interpolation> method = terrain::parseInterpolation(name);
  if (method == terrain::Interpolation::kBicubic ||
      method == terrain::Interpolation::kCubicBSpline) {
    return method;
  }
  return std::nullopt;
}

// `terrain`: exactly one of file and generate, plus raster options, frame and obstacles.
terrain::TerrainSource parseTerrain(const Context& ctx, const Field& field) {
  const MapReader map(
      ctx, field, {"file", "generate", "cell", "z_scale", "frame", "obstacles", "interpolation"});
  terrain::TerrainSource source;
  const std::optional<Field> file = map.find("file");
  const std::optional<Field> generate = map.find("generate");
  if (file && generate) {
    ctx.fail(generate->key_mark, map.path(), "give either file or generate, not both");
  }
  if (!file && !generate) {
    map.fail("", "give one of file (an elevation raster) or generate (a synthetic terrain)");
  }
  if (file) source.file = readPath(ctx, *file);
  if (generate) source.generate = parseGenerate(ctx, *generate);

  if (const std::optional<Field> cell = map.find("cell")) {
    if (generate) {
      ctx.fail(cell->key_mark, cell->path,
               "not allowed with terrain.generate (set the cell size with generate.cell)");
    }
    source.raster.cell = readNumber(ctx, *cell, Range::positive());
  }
  if (const std::optional<Field> z_scale = map.find("z_scale")) {
    source.raster.z_scale = readNumber(ctx, *z_scale, Range::any());
    if (source.raster.z_scale == 0.0) failAt(ctx, *z_scale, "must not be 0");
  }
  if (const std::optional<Field> frame = map.find("frame")) {
    source.frame = readEnum<terrain::CoordinateFrame>(ctx, *frame, parseFrame, {"local", "world"});
  }
  if (const std::optional<Field> interpolation = map.find("interpolation")) {
    source.interpolation = readEnum<terrain::Interpolation>(
        ctx, *interpolation, parseSmoothInterpolation, {"bspline", "bicubic"});
  }
  if (const std::optional<Field> obstacles = map.find("obstacles")) {
    source.obstacles = parseObstacles(ctx, *obstacles);
    if (source.obstacles.band && !source.obstacles.file && !file) {
      ctx.fail(obstacles->key_mark, obstacles->path + ".band",
               "a band of the terrain's raster needs terrain.file (or give obstacles.file)");
    }
  }
  return source;
}

// `vehicle.limits`: every limit optional and > 0; pitch and roll limits in (0, 90) deg.
VehicleLimits parseLimits(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field,
                      {"v_max", "a_max", "omega_max", "kappa_max", "sigma_max", "pitch_max",
                       "pitch_max_deg", "roll_max", "roll_max_deg"});
  VehicleLimits limits;
  // The ranges of ground rovers: a limit outside them (1e-12, 1e300) is a typo or a unit
  // error, and the solvers' scaling would not survive it.
  map.readNumberInto("v_max", Range::closed(kMinSpeedLimit, kMaxSpeedLimit, "m/s"), limits.v_max);
  map.readNumberInto("a_max", Range::closed(1e-3, 100.0, "m/s^2"), limits.a_max);
  map.readNumberInto("omega_max", Range::closed(1e-3, 100.0, "rad/s"), limits.omega_max);
  map.readNumberInto("kappa_max", Range::closed(1e-3, 1000.0, "1/m"), limits.kappa_max);
  map.readNumberInto("sigma_max", Range::closed(1e-4, 1e4, "1/(m s)"), limits.sigma_max);
  map.readAngleInto("pitch_max", rightAngleRangeDeg(), limits.pitch_max);
  map.readAngleInto("roll_max", rightAngleRangeDeg(), limits.roll_max);
  return limits;
}

// `vehicle.tables`: optional look-up table paths.
VehicleTables parseTables(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field, {"pitch", "roll_curvature"});
  VehicleTables tables;
  if (const std::optional<Field> pitch = map.find("pitch")) tables.pitch = readPath(ctx, *pitch);
  if (const std::optional<Field> roll = map.find("roll_curvature")) {
    tables.roll_curvature = readPath(ctx, *roll);
  }
  return tables;
}

// `vehicle`: model, limits, tables.
VehicleSpec parseVehicle(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field, {"model", "limits", "tables"});
  VehicleSpec vehicle;
  if (const std::optional<Field> model = map.find("model")) {
    vehicle.model =
        readEnum<VehicleModelKind>(ctx, *model, parseVehicleModelKind, vehicleModelNames());
  }
  if (const std::optional<Field> limits = map.find("limits")) {
    vehicle.limits = parseLimits(ctx, *limits);
  }
  if (const std::optional<Field> tables = map.find("tables")) {
    vehicle.tables = parseTables(ctx, *tables);
  }
  return vehicle;
}

// `start` / `goal`: x, y and heading required; v and omega within `limits`.
BoundaryState parseBoundary(const Context& ctx, const Field& field, const VehicleLimits& limits) {
  const MapReader map(ctx, field, {"x", "y", "heading", "heading_deg", "v", "omega"});
  BoundaryState state;
  state.x = map.requiredNumber("x", Range::any());
  state.y = map.requiredNumber("y", Range::any());
  const std::optional<double> heading = map.optionalAngle("heading", Range::any());
  if (!heading) {
    map.fail("heading", "missing required key (give heading_deg [deg] or heading [rad])");
  }
  state.heading = wrapAngle(*heading);
  if (const std::optional<Field> v = map.find("v")) {
    state.v = readNumber(ctx, *v, Range::nonNegative());
    if (state.v > limits.v_max) {
      failAt(ctx, *v,
             "must be <= vehicle.limits.v_max = " + formatNumber(limits.v_max) + " m/s (got " +
                 v->value.Scalar() + ")");
    }
  }
  if (const std::optional<Field> omega = map.find("omega")) {
    state.omega = readNumber(ctx, *omega, Range::any());
    if (std::abs(state.omega) > limits.omega_max) {
      failAt(ctx, *omega,
             "|omega| must be <= vehicle.limits.omega_max = " + formatNumber(limits.omega_max) +
                 " rad/s (got " + omega->value.Scalar() + ")");
    }
  }
  return state;
}

// `cost`.
CostSpec parseCost(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field, {"kind", "alpha"});
  CostSpec cost;
  if (const std::optional<Field> kind = map.find("kind")) {
    cost.kind = readEnum<CostKind>(ctx, *kind, parseCostKind, costKindNames());
  }
  map.readNumberInto("alpha", Range::nonNegative(), cost.alpha);
  return cost;
}

// `solver.tolerance`, into `solver`.
void parseTolerance(const Context& ctx, const Field& field, SolverSpec& solver) {
  const MapReader map(ctx, field, {"position_m", "heading_rad", "lagrangian_gradient"});
  map.readNumberInto("position_m", Range::positive(), solver.tolerance_position_m);
  map.readNumberInto("heading_rad", Range::positive(), solver.tolerance_heading_rad);
  map.readNumberInto("lagrangian_gradient", Range::positive(),
                     solver.tolerance_lagrangian_gradient);
}

// A key naming one of `choices` (name, value), into `value` when present.
template <typename Value>
void readChoiceInto(const Context& ctx, const MapReader& map, const char* key,
                    const std::vector<std::pair<std::string, Value>>& choices, Value& value) {
  if (const std::optional<Field> found = map.find(key)) {
    std::vector<std::string> names;
    for (const auto& choice : choices) names.push_back(choice.first);
    value = readEnum<Value>(
        ctx, *found,
        [&](const std::string& text) -> std::optional<Value> {
          for (const auto& [name, choice] : choices) {
            if (name == text) return choice;
          }
          return std::nullopt;
        },
        names);
  }
}

// `solver`.
SolverSpec parseSolver(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field,
                      {"method",
                       "intervals",
                       "max_iterations",
                       "tolerance",
                       "time_limit_s",
                       "yaw_rate_order",
                       "speed_order",
                       "scheme",
                       "shooting_controls",
                       "hessian",
                       "control_effort",
                       "mesh_refinement_rounds",
                       "mesh_refinement_tolerance",
                       "min_clearance_m",
                       "max_intervals",
                       "initial_guess",
                       "transcription_max_iterations",
                       "ipopt_max_iterations",
                       "seed_time_s",
                       "first_seed_time_s",
                       "search_improve_milestones",
                       "search_improvements"});
  SolverSpec solver;
  if (const std::optional<Field> method = map.find("method")) {
    solver.method = readEnum<SolverMethod>(ctx, *method, parseSolverMethod, solverMethodNames());
  }
  if (map.find("intervals")) {
    int intervals = 40;
    map.readIntInto("intervals", kMinIntervals, kMaxIntervals, intervals);
    solver.intervals = intervals;
  }
  map.readIntInto("max_intervals", kMinIntervals, kMaxIntervals, solver.max_intervals);
  if (solver.intervals && solver.max_intervals < *solver.intervals) {
    map.fail("max_intervals", "must be >= intervals (" + std::to_string(*solver.intervals) +
                                  "), got " + std::to_string(solver.max_intervals));
  }
  readChoiceInto<InitialGuessKind>(
      ctx, map, "initial_guess",
      {{"auto", InitialGuessKind::kAuto}, {"flat", InitialGuessKind::kFlat}}, solver.initial_guess);
  map.readIntInto("max_iterations", kMinIterations, kMaxIterations, solver.max_iterations);
  if (map.find("transcription_max_iterations")) {
    int iterations = 1;
    map.readIntInto("transcription_max_iterations", kMinIterations, kMaxIterations, iterations);
    solver.transcription_max_iterations = iterations;
  }
  if (map.find("ipopt_max_iterations")) {
    int iterations = 1;
    map.readIntInto("ipopt_max_iterations", kMinIterations, kMaxIterations, iterations);
    solver.ipopt_max_iterations = iterations;
  }
  map.readIntInto("yaw_rate_order", 1, 8, solver.yaw_rate_order);
  map.readIntInto("speed_order", 1, 8, solver.speed_order);
  if (const std::optional<Field> tolerance = map.find("tolerance")) {
    parseTolerance(ctx, *tolerance, solver);
  }
  if (const std::optional<double> limit =
          map.optionalNumber("time_limit_s", Range::nonNegative())) {
    solver.time_limit_s = limit;
  }
  solver.seed_time_s = map.optionalNumber("seed_time_s", Range::positive());
  solver.first_seed_time_s = map.optionalNumber("first_seed_time_s", Range::positive());
  for (const auto& [key, max_value, target] :
       {std::tuple{"search_improve_milestones", kMaxSearchMilestones,
                   &solver.search_improve_milestones},
        std::tuple{"search_improvements", kMaxSearchImprovements, &solver.search_improvements}}) {
    if (map.find(key)) {
      int value = 0;
      map.readIntInto(key, 0, max_value, value);
      *target = value;
    }
  }
  using ocp::TranscriptionScheme;
  readChoiceInto<TranscriptionScheme>(ctx, map, "scheme",
                                      {{"hermite_simpson", TranscriptionScheme::kHermiteSimpson},
                                       {"trapezoidal", TranscriptionScheme::kTrapezoidal}},
                                      solver.scheme);
  readChoiceInto<ocp::ShootingControls>(ctx, map, "shooting_controls",
                                        {{"linear", ocp::ShootingControls::kPiecewiseLinear},
                                         {"constant", ocp::ShootingControls::kPiecewiseConstant}},
                                        solver.shooting_controls);
  readChoiceInto<std::optional<ocp::TranscriptionHessian>>(
      ctx, map, "hessian",
      {{"auto", std::nullopt},
       {"exact", ocp::TranscriptionHessian::kExact},
       {"limited_memory", ocp::TranscriptionHessian::kLimitedMemory}},
      solver.hessian);
  map.readNumberInto("control_effort", Range::nonNegative(), solver.control_effort);
  map.readIntInto("mesh_refinement_rounds", 0, 10, solver.mesh_refinement_rounds);
  map.readNumberInto("mesh_refinement_tolerance", Range::positive(),
                     solver.mesh_refinement_tolerance);
  solver.min_clearance_m = map.optionalNumber("min_clearance_m", Range::nonNegative());
  return solver;
}

// `planner`.
PlannerSpec parsePlanner(const Context& ctx, const Field& field) {
  const MapReader map(ctx, field,
                      {"kind",
                       "time_limit_s",
                       "max_iterations",
                       "seed",
                       "homotopy_classes",
                       "frame_radius_m",
                       "goal_position_tolerance_m",
                       "goal_heading_tolerance",
                       "goal_heading_tolerance_deg",
                       "goal_speed_tolerance",
                       "lattice_resolution_m",
                       "heading_count",
                       "primitives",
                       "primitive_speed",
                       "algorithm",
                       "initial_epsilon",
                       "epsilon_step",
                       "frame_anchor",
                       "heuristic_weight",
                       "max_signature_length"});
  PlannerSpec planner;
  if (const std::optional<Field> kind = map.find("kind")) {
    planner.kind = readEnum<PlannerKind>(ctx, *kind, parsePlannerKind, plannerKindNames());
  }
  planner.time_limit_s = map.optionalNumber("time_limit_s", Range::nonNegative());
  if (map.find("max_iterations")) {
    int iterations = 1;
    map.readIntInto("max_iterations", 1, std::numeric_limits<int>::max(), iterations);
    planner.max_iterations = iterations;
  }
  map.readSeedInto("seed", planner.seed);
  map.readIntInto("homotopy_classes", kMinHomotopyClasses, kMaxHomotopyClasses,
                  planner.homotopy_classes);
  map.readNumberInto("frame_radius_m", Range::positive(), planner.frame_radius_m);
  planner.goal_position_tolerance_m =
      map.optionalNumber("goal_position_tolerance_m", Range::positive());
  map.readAngleInto("goal_heading_tolerance", Range::openInterval(0.0, 360.0, "deg"),
                    planner.goal_heading_tolerance);
  map.readNumberInto("goal_speed_tolerance", Range::positive(), planner.goal_speed_tolerance);
  planner.lattice_resolution_m = map.optionalNumber("lattice_resolution_m", Range::positive());
  map.readIntInto("heading_count", 4, 1024, planner.heading_count);
  if (const std::optional<Field> file = map.find("primitives")) {
    planner.primitives = readPath(ctx, *file);
  }
  planner.primitive_speed = map.optionalNumber("primitive_speed", Range::positive());
  readChoiceInto<search::LatticeAlgorithm>(ctx, map, "algorithm",
                                           {{"arastar", search::LatticeAlgorithm::kAraStar},
                                            {"astar", search::LatticeAlgorithm::kAStar}},
                                           planner.algorithm);
  readChoiceInto<search::FrameAnchor>(ctx, map, "frame_anchor",
                                      {{"map_center", search::FrameAnchor::kMapCenter},
                                       {"start", search::FrameAnchor::kStart},
                                       {"midpoint", search::FrameAnchor::kMidpoint}},
                                      planner.frame_anchor);
  map.readNumberInto("initial_epsilon", Range::atLeast(1.0), planner.initial_epsilon);
  map.readNumberInto("epsilon_step", Range::positive(), planner.epsilon_step);
  map.readNumberInto("heuristic_weight", Range::atLeast(1.0), planner.heuristic_weight);
  if (map.find("max_signature_length")) {
    int length = 0;
    map.readIntInto("max_signature_length", 1, 10000, length);
    planner.max_signature_length = length;
  }
  return planner;
}

// `refine`.
RefineSpec parseRefine(const Context& ctx, const Field& field) {
  const MapReader map(
      ctx, field,
      {"method", "interval_length_m", "min_intervals", "max_intervals", "min_clearance_m",
       "limit_margin", "speed_margin", "control_effort", "max_iterations", "time_limit_s",
       "parametric_max_length_m", "parametric_min_clearance_m", "coarse_interval_length_m",
       "endpoint_tolerance_m", "warm_start_time_ratio"});
  RefineSpec refine;
  if (const std::optional<Field> method = map.find("method")) {
    refine.method = readEnum<refine::RefineMethod>(
        ctx, *method, [](const std::string& text) { return refine::parseRefineMethod(text); },
        refine::refineMethodNames());
  }
  map.readNumberInto("interval_length_m", Range::positive(), refine.interval_length_m);
  map.readIntInto("min_intervals", kMinIntervals, kMaxIntervals, refine.min_intervals);
  map.readIntInto("max_intervals", kMinIntervals, kMaxIntervals, refine.max_intervals);
  if (refine.max_intervals < refine.min_intervals) {
    map.fail("max_intervals", "must be >= min_intervals (" + std::to_string(refine.min_intervals) +
                                  "), got " + std::to_string(refine.max_intervals));
  }
  map.readNumberInto("min_clearance_m", Range::nonNegative(), refine.min_clearance_m);
  const Range margin{Range::Bound::kClosed, 0.0, Range::Bound::kOpen, 0.5, ""};
  map.readNumberInto("limit_margin", margin, refine.limit_margin);
  map.readNumberInto("speed_margin", margin, refine.speed_margin);
  map.readNumberInto("control_effort", Range::nonNegative(), refine.control_effort);
  map.readIntInto("max_iterations", kMinIterations, kMaxIterations, refine.max_iterations);
  refine.time_limit_s = map.optionalNumber("time_limit_s", Range::nonNegative());
  map.readNumberInto("parametric_max_length_m", Range::nonNegative(),
                     refine.parametric_max_length_m);
  map.readNumberInto("parametric_min_clearance_m", Range::nonNegative(),
                     refine.parametric_min_clearance_m);
  map.readNumberInto("coarse_interval_length_m", Range::positive(),
                     refine.coarse_interval_length_m);
  map.readNumberInto("endpoint_tolerance_m", Range::positive(), refine.endpoint_tolerance_m);
  map.readNumberInto("warm_start_time_ratio", Range::atLeast(1.0), refine.warm_start_time_ratio);
  return refine;
}

// The single YAML document of the text; throws InputError for malformed YAML, no document, or
// more than one.
YAML::Node loadDocument(const Context& ctx, const std::string& yaml_text) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(yaml_text);
  } catch (const YAML::Exception& error) {
    ctx.fail(error.mark, "", "invalid YAML: " + error.msg);
  }
  if (documents.empty() || (documents.size() == 1 && documents.front().IsNull())) {
    throw InputError(ctx.displayName() +
                     ": the problem file is empty (expected a map with terrain, start and goal)");
  }
  if (documents.size() > 1) {
    ctx.fail(documents[1].Mark(), "",
             "holds " + std::to_string(documents.size()) + " YAML documents; expected one");
  }
  return documents.front();
}

// The top-level map: terrain, start and goal required; vehicle read before start and goal.
ProblemSpec parseRoot(const Context& ctx, const YAML::Node& root) {
  const Field root_field{root, root.Mark(), ""};
  if (!root.IsMap()) {
    failAt(ctx, root_field,
           "the top level must be a map of sections (terrain, vehicle, start, goal, cost, "
           "solver, planner, refine), got " +
               describeNode(root));
  }
  const MapReader map(
      ctx, root_field,
      {"terrain", "vehicle", "start", "goal", "cost", "solver", "planner", "refine"});
  ProblemSpec problem;
  problem.source_file = ctx.displayName();
  problem.terrain = parseTerrain(ctx, map.require("terrain"));
  problem.pose_frame = problem.terrain.frame;
  if (const std::optional<Field> vehicle = map.find("vehicle")) {
    problem.vehicle = parseVehicle(ctx, *vehicle);
  }
  // Both boundary states are checked against the limits, so vehicle is read first.
  problem.start = parseBoundary(ctx, map.require("start"), problem.vehicle.limits);
  problem.goal = parseBoundary(ctx, map.require("goal"), problem.vehicle.limits);
  if (const std::optional<Field> cost = map.find("cost")) problem.cost = parseCost(ctx, *cost);
  if (const std::optional<Field> solver = map.find("solver")) {
    problem.solver = parseSolver(ctx, *solver);
  }
  if (const std::optional<Field> planner = map.find("planner")) {
    problem.planner = parsePlanner(ctx, *planner);
  }
  if (const std::optional<Field> refine = map.find("refine")) {
    problem.refine = parseRefine(ctx, *refine);
  }
  return problem;
}

// ------------------------------------------------------------------------------------------
// Files.

// The whole file as text; throws InputError when it is missing, unreadable, a directory, or
// larger than kMaxProblemFileBytes.
std::string readProblemFile(const fs::path& yaml_file) {
  const std::string name = yaml_file.string();
  std::error_code status_error;
  const fs::file_status status = fs::status(yaml_file, status_error);
  if (status.type() == fs::file_type::not_found) {
    throw InputError(name + ": cannot read the problem file: no such file");
  }
  if (status_error) {
    throw InputError(name + ": cannot read the problem file: " + status_error.message());
  }
  if (fs::is_directory(status)) {
    throw InputError(name + ": cannot read the problem file: it is a directory");
  }
  errno = 0;
  std::ifstream in(yaml_file, std::ios::binary);
  if (!in) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "cannot open it";
    throw InputError(name + ": cannot read the problem file: " + reason);
  }
  std::string text;
  std::vector<char> chunk(kReadChunkBytes);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxProblemFileBytes) {
      throw InputError(name + ": the problem file is larger than " +
                       std::to_string(kMaxProblemFileBytes >> 20) + " MiB");
    }
  }
  if (in.bad()) throw InputError(name + ": cannot read the problem file: read error");
  return text;
}

// ------------------------------------------------------------------------------------------
// Poses on the terrain.

std::string formatPoint(const Eigen::Vector2d& point) {
  return "(" + formatCoordinate(point.x()) + ", " + formatCoordinate(point.y()) + ")";
}

// Converts one pose to local coordinates and checks it lies on a free cell of `map`; throws
// InputError "<file>: <name>: ..." otherwise.
Eigen::Vector2d localPoseOnMap(const std::string& file, const char* name,
                               const BoundaryState& state, bool from_world,
                               const terrain::ElevationMap& map) {
  const terrain::GridGeometry& geometry = map.geometry();
  const Eigen::Vector2d given(state.x, state.y);
  const Eigen::Vector2d local = from_world ? geometry.toLocal(given) : given;
  std::string where = "(x, y) = " + formatPoint(given) + " m";
  if (from_world) where += " (world; local " + formatPoint(local) + " m)";
  const std::string prefix = file + ": " + name + ": " + where;

  const std::optional<terrain::CellIndex> cell =
      geometry.contains(local) ? geometry.cellAt(local) : std::nullopt;
  if (!cell) {
    std::string extent = "local extent [0, " + formatCoordinate(geometry.width()) + "] x [0, " +
                         formatCoordinate(geometry.height()) + "] m";
    if (from_world) {
      const Eigen::Vector2d low = geometry.toWorld(Eigen::Vector2d::Zero());
      const Eigen::Vector2d high = geometry.toWorld({geometry.width(), geometry.height()});
      extent = "world extent [" + formatCoordinate(low.x()) + ", " + formatCoordinate(high.x()) +
               "] x [" + formatCoordinate(low.y()) + ", " + formatCoordinate(high.y()) + "] m, " +
               extent;
    }
    throw InputError(prefix + " is outside the map (" + extent + ")");
  }
  const std::string cell_text =
      "(row " + std::to_string(cell->row) + ", col " + std::to_string(cell->col) + ")";
  if (map.isNoData(*cell)) throw InputError(prefix + " is on a no-data cell " + cell_text);
  if (map.isLethal(*cell)) throw InputError(prefix + " is on a lethal cell " + cell_text);
  return local;
}

}  // namespace

ProblemSpec parseProblem(const std::string& yaml_text, const std::filesystem::path& base_dir,
                         const std::string& display_name) {
  const Context ctx(display_name, base_dir);
  try {
    return parseRoot(ctx, loadDocument(ctx, yaml_text));
  } catch (const YAML::Exception& error) {
    // Not expected (every access is checked first), but no yaml-cpp exception may escape.
    ctx.fail(error.mark, "", "cannot read the YAML: " + error.msg);
  }
}

ProblemSpec loadProblem(const std::filesystem::path& yaml_file) {
  return parseProblem(readProblemFile(yaml_file), yaml_file.parent_path(), yaml_file.string());
}

ResolvedPoses resolvePoses(const ProblemSpec& problem, const terrain::ElevationMap& map) {
  const std::string file = problem.source_file.string();
  const bool from_world = problem.pose_frame == terrain::CoordinateFrame::kWorld;
  const Eigen::Vector2d start = localPoseOnMap(file, "start", problem.start, from_world, map);
  const Eigen::Vector2d goal = localPoseOnMap(file, "goal", problem.goal, from_world, map);
  ResolvedPoses poses{problem.start, problem.goal};
  poses.start.x = start.x();
  poses.start.y = start.y();
  poses.goal.x = goal.x();
  poses.goal.y = goal.y();
  return poses;
}

}  // namespace terratraj::apps
