// Tests of the problem-file loader (apps/problem_loader.hpp, docs/problem-file.md).

#include "terratraj/apps/problem_loader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/grid_geometry.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr double kTol = 1e-12;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The example of the contract (shared/spec/interface.md), verbatim.
const char* const kContractExample = R"(terrain:
  file: data/dem.tif          # any raster GDAL reads
                              # relative paths are relative to this YAML file
  # generate: {kind: hills, rows: 256, cols: 256, cell: 0.25, seed: 1}
  cell: 0.25                  # optional
  z_scale: 1.0                # optional: multiplies heights
  frame: local                # local | world
  obstacles:                  # optional lethal layer
    file: data/lethal.tif     # non-zero = lethal
    max_slope_deg: 35         # and/or: cells steeper than this are lethal
vehicle:
  model: rocker_bogie         # point | four_wheel | rocker_bogie | segway_rmp
  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5, pitch_max_deg: 17, roll_max_deg: 20}
  tables:                     # optional kinodynamic look-up tables (JSON, format below)
    pitch: tables/pitch_vmax.json
    roll_curvature: tables/roll_curvature_vmax.json
start: {x: 2.0, y: 3.0, heading_deg: 0, v: 0.0, omega: 0.0}
goal:  {x: 6.0, y: 3.0, heading_deg: 0, v: 0.0, omega: 0.0}
cost: {kind: time, alpha: 0.0}            # time | slope_dwell
solver:
  method: newton              # newton | newton_fd | ipopt | ceres | shooting | collocation
  intervals: 40               # for shooting / collocation
  max_iterations: 100
  tolerance: {position_m: 0.001, heading_rad: 0.001}
planner:
  kind: prm                   # prm | lattice | taeasl
  time_limit_s: 1.0
  seed: 1
  homotopy_classes: 3         # taeasl: how many distinct classes to return at most
  frame_radius_m: 10.0        # taeasl
)";

// The smallest valid problem: a generated terrain, a start and a goal.
const char* const kMinimal = R"(terrain:
  generate: {kind: hills}
start: {x: 2.0, y: 3.0, heading_deg: 0}
goal: {x: 6.0, y: 3.0, heading_deg: 90}
)";

ProblemSpec parse(const std::string& yaml, const fs::path& base_dir = "/proj") {
  return parseProblem(yaml, base_dir, "problem.yaml");
}

// The message of the InputError that parsing `yaml` throws ("" and a test failure if none).
std::string parseError(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const InputError& error) {
    return error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << "unexpected exception type: " << error.what();
    return "";
  }
  ADD_FAILURE() << "no InputError for:\n" << yaml;
  return "";
}

// kMinimal with one more section (or a replaced one, when the key is terrain/start/goal).
std::string minimalWith(const std::string& extra) { return std::string(kMinimal) + extra; }

// A problem with `start` replaced.
std::string withStart(const std::string& start) {
  return "terrain: {generate: {kind: flat}}\nstart: " + start +
         "\ngoal: {x: 6.0, y: 3.0, heading_deg: 0}\n";
}

// A problem with `terrain` replaced.
std::string withTerrain(const std::string& terrain) {
  return "terrain: " + terrain +
         "\nstart: {x: 2.0, y: 3.0, heading_deg: 0}\ngoal: {x: 6.0, y: 3.0, heading_deg: 0}\n";
}

// ---------------------------------------------------------------------------------------------
// Valid files.

TEST(ProblemLoader, ContractExampleParses) {
  const ProblemSpec p = parse(kContractExample);
  EXPECT_EQ(p.source_file, fs::path("problem.yaml"));

  ASSERT_TRUE(p.terrain.file.has_value());
  EXPECT_EQ(*p.terrain.file, fs::path("/proj/data/dem.tif"));
  EXPECT_FALSE(p.terrain.generate.has_value());
  ASSERT_TRUE(p.terrain.raster.cell.has_value());
  EXPECT_DOUBLE_EQ(*p.terrain.raster.cell, 0.25);
  EXPECT_DOUBLE_EQ(p.terrain.raster.z_scale, 1.0);
  EXPECT_EQ(p.terrain.frame, terrain::CoordinateFrame::kLocal);
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kLocal);
  ASSERT_TRUE(p.terrain.obstacles.file.has_value());
  EXPECT_EQ(*p.terrain.obstacles.file, fs::path("/proj/data/lethal.tif"));
  ASSERT_TRUE(p.terrain.obstacles.max_slope.has_value());
  EXPECT_NEAR(*p.terrain.obstacles.max_slope, 35.0 * kDeg, kTol);

  EXPECT_EQ(p.vehicle.model, VehicleModelKind::kRockerBogie);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.v_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.a_max, 0.5);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.omega_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.kappa_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.sigma_max, 0.5);
  EXPECT_NEAR(p.vehicle.limits.pitch_max, 17.0 * kDeg, kTol);
  EXPECT_NEAR(p.vehicle.limits.roll_max, 20.0 * kDeg, kTol);
  ASSERT_TRUE(p.vehicle.tables.pitch.has_value());
  EXPECT_EQ(*p.vehicle.tables.pitch, fs::path("/proj/tables/pitch_vmax.json"));
  ASSERT_TRUE(p.vehicle.tables.roll_curvature.has_value());
  EXPECT_EQ(*p.vehicle.tables.roll_curvature, fs::path("/proj/tables/roll_curvature_vmax.json"));

  EXPECT_DOUBLE_EQ(p.start.x, 2.0);
  EXPECT_DOUBLE_EQ(p.start.y, 3.0);
  EXPECT_DOUBLE_EQ(p.start.heading, 0.0);
  EXPECT_DOUBLE_EQ(p.start.v, 0.0);
  EXPECT_DOUBLE_EQ(p.start.omega, 0.0);
  EXPECT_DOUBLE_EQ(p.goal.x, 6.0);
  EXPECT_DOUBLE_EQ(p.goal.y, 3.0);

  EXPECT_EQ(p.cost.kind, CostKind::kTime);
  EXPECT_DOUBLE_EQ(p.cost.alpha, 0.0);
  EXPECT_EQ(p.solver.method, SolverMethod::kNewton);
  EXPECT_EQ(p.solver.intervals, std::optional<int>(40));
  EXPECT_EQ(p.solver.max_iterations, 100);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_position_m, 0.001);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_heading_rad, 0.001);
  EXPECT_FALSE(p.solver.time_limit_s.has_value());
  EXPECT_EQ(p.planner.kind, PlannerKind::kPrm);
  EXPECT_DOUBLE_EQ(p.planner.time_limit_s, 1.0);
  EXPECT_EQ(p.planner.seed, 1u);
  EXPECT_EQ(p.planner.homotopy_classes, 3);
  EXPECT_DOUBLE_EQ(p.planner.frame_radius_m, 10.0);
}

TEST(ProblemLoader, MinimalProblemTakesDefaults) {
  const ProblemSpec p = parse(kMinimal);
  const terrain::GeneratorOptions generator_defaults;
  ASSERT_TRUE(p.terrain.generate.has_value());
  EXPECT_FALSE(p.terrain.file.has_value());
  EXPECT_EQ(p.terrain.generate->kind, terrain::TerrainKind::kHills);
  EXPECT_EQ(p.terrain.generate->rows, generator_defaults.rows);
  EXPECT_EQ(p.terrain.generate->cols, generator_defaults.cols);
  EXPECT_DOUBLE_EQ(p.terrain.generate->cell, generator_defaults.cell);
  EXPECT_EQ(p.terrain.generate->seed, generator_defaults.seed);
  EXPECT_FALSE(p.terrain.raster.cell.has_value());
  EXPECT_DOUBLE_EQ(p.terrain.raster.z_scale, 1.0);
  EXPECT_EQ(p.terrain.frame, terrain::CoordinateFrame::kLocal);
  EXPECT_FALSE(p.terrain.obstacles.file.has_value());
  EXPECT_FALSE(p.terrain.obstacles.max_slope.has_value());

  const VehicleSpec vehicle_defaults;
  EXPECT_EQ(p.vehicle.model, VehicleModelKind::kPoint);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.v_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.a_max, 0.5);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.omega_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.kappa_max, 1.0);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.sigma_max, 0.5);
  EXPECT_NEAR(p.vehicle.limits.pitch_max, 17.0 * kDeg, kTol);
  EXPECT_NEAR(p.vehicle.limits.roll_max, 20.0 * kDeg, kTol);
  EXPECT_FALSE(p.vehicle.tables.pitch.has_value());
  EXPECT_FALSE(p.vehicle.tables.roll_curvature.has_value());

  EXPECT_DOUBLE_EQ(p.start.v, 0.0);
  EXPECT_DOUBLE_EQ(p.start.omega, 0.0);
  EXPECT_NEAR(p.goal.heading, 90.0 * kDeg, kTol);

  EXPECT_EQ(p.cost.kind, CostKind::kTime);
  EXPECT_DOUBLE_EQ(p.cost.alpha, 0.0);
  EXPECT_EQ(p.solver.method, SolverMethod::kAuto);
  EXPECT_EQ(p.solver.initial_guess, InitialGuessKind::kAuto);
  EXPECT_FALSE(p.solver.intervals.has_value());
  EXPECT_EQ(p.solver.max_iterations, 100);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_position_m, 0.001);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_heading_rad, 0.001);
  EXPECT_FALSE(p.solver.time_limit_s.has_value());
  EXPECT_EQ(p.planner.kind, PlannerKind::kPrm);
  EXPECT_DOUBLE_EQ(p.planner.time_limit_s, 1.0);
  EXPECT_EQ(p.planner.seed, 1u);
  EXPECT_EQ(p.planner.homotopy_classes, 3);
  EXPECT_DOUBLE_EQ(p.planner.frame_radius_m, 10.0);
}

TEST(ProblemLoader, GenerateOptionsAndOtherSections) {
  const ProblemSpec p = parse(R"(terrain:
  generate: {kind: dead_end, rows: 10, cols: 20, cell: 0.5, seed: 18446744073709551615}
  z_scale: -2.5
  frame: world
  obstacles: {max_slope: 0.5}
vehicle: {model: segway_rmp, limits: {pitch_max: 0.3, roll_max_deg: 45, v_max: 2}}
start: {x: -1e3, y: +3, heading: 1.0, v: 2, omega: -1}
goal: {x: .5, y: 7., heading_deg: 270}
cost: {kind: slope_dwell, alpha: 2.5}
solver: {method: collocation, intervals: 2, max_iterations: 1, time_limit_s: 0.5,
         tolerance: {position_m: 1e-6, heading_rad: 2e-6}, initial_guess: flat,
         transcription_max_iterations: 77, ipopt_max_iterations: 55}
planner: {kind: taeasl, time_limit_s: 0, seed: 0, homotopy_classes: 1, frame_radius_m: 2.5}
)");
  EXPECT_EQ(p.solver.initial_guess, InitialGuessKind::kFlat);
  ASSERT_TRUE(p.solver.transcription_max_iterations.has_value());
  EXPECT_EQ(*p.solver.transcription_max_iterations, 77);
  ASSERT_TRUE(p.solver.ipopt_max_iterations.has_value());
  EXPECT_EQ(*p.solver.ipopt_max_iterations, 55);
  ASSERT_TRUE(p.terrain.generate.has_value());
  EXPECT_EQ(p.terrain.generate->kind, terrain::TerrainKind::kDeadEnd);
  EXPECT_EQ(p.terrain.generate->rows, 10);
  EXPECT_EQ(p.terrain.generate->cols, 20);
  EXPECT_DOUBLE_EQ(p.terrain.generate->cell, 0.5);
  EXPECT_EQ(p.terrain.generate->seed, std::numeric_limits<std::uint64_t>::max());
  EXPECT_DOUBLE_EQ(p.terrain.raster.z_scale, -2.5);
  EXPECT_EQ(p.terrain.frame, terrain::CoordinateFrame::kWorld);
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kWorld);
  ASSERT_TRUE(p.terrain.obstacles.max_slope.has_value());
  EXPECT_DOUBLE_EQ(*p.terrain.obstacles.max_slope, 0.5);
  EXPECT_FALSE(p.terrain.obstacles.file.has_value());
  EXPECT_EQ(p.vehicle.model, VehicleModelKind::kSegwayRmp);
  EXPECT_DOUBLE_EQ(p.vehicle.limits.pitch_max, 0.3);
  EXPECT_NEAR(p.vehicle.limits.roll_max, 45.0 * kDeg, kTol);
  EXPECT_DOUBLE_EQ(p.start.x, -1000.0);
  EXPECT_DOUBLE_EQ(p.start.y, 3.0);
  EXPECT_DOUBLE_EQ(p.start.heading, 1.0);
  EXPECT_DOUBLE_EQ(p.start.v, 2.0);
  EXPECT_DOUBLE_EQ(p.start.omega, -1.0);
  EXPECT_DOUBLE_EQ(p.goal.x, 0.5);
  EXPECT_DOUBLE_EQ(p.goal.y, 7.0);
  EXPECT_NEAR(p.goal.heading, -90.0 * kDeg, kTol);  // wrapped to (-pi, pi]
  EXPECT_EQ(p.cost.kind, CostKind::kSlopeDwell);
  EXPECT_DOUBLE_EQ(p.cost.alpha, 2.5);
  EXPECT_EQ(p.solver.method, SolverMethod::kCollocation);
  EXPECT_EQ(p.solver.intervals, std::optional<int>(2));
  EXPECT_EQ(p.solver.max_iterations, 1);
  ASSERT_TRUE(p.solver.time_limit_s.has_value());
  EXPECT_DOUBLE_EQ(*p.solver.time_limit_s, 0.5);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_position_m, 1e-6);
  EXPECT_DOUBLE_EQ(p.solver.tolerance_heading_rad, 2e-6);
  EXPECT_EQ(p.planner.kind, PlannerKind::kTaeasl);
  EXPECT_DOUBLE_EQ(p.planner.time_limit_s, 0.0);
  EXPECT_EQ(p.planner.seed, 0u);
  EXPECT_EQ(p.planner.homotopy_classes, 1);
  EXPECT_DOUBLE_EQ(p.planner.frame_radius_m, 2.5);
}

TEST(ProblemLoader, HeadingOfHalfTurnIsPi) {
  const ProblemSpec p = parse(withStart("{x: 0, y: 0, heading_deg: -180}"));
  EXPECT_NEAR(p.start.heading, 180.0 * kDeg, kTol);
}

TEST(ProblemLoader, RelativePathsResolveAgainstBaseDir) {
  const ProblemSpec p = parse(R"(terrain:
  file: maps/dem.asc
  obstacles: {file: /abs/lethal.tif}
vehicle:
  tables: {pitch: ../tables/p.json, roll_curvature: /abs/rc.json}
start: {x: 2.0, y: 3.0, heading_deg: 0}
goal: {x: 6.0, y: 3.0, heading_deg: 0}
)",
                              "/data/proj");
  EXPECT_EQ(*p.terrain.file, fs::path("/data/proj/maps/dem.asc"));
  EXPECT_EQ(*p.terrain.obstacles.file, fs::path("/abs/lethal.tif"));
  EXPECT_EQ(*p.vehicle.tables.pitch, fs::path("/data/proj/../tables/p.json"));
  EXPECT_EQ(*p.vehicle.tables.roll_curvature, fs::path("/abs/rc.json"));

  const ProblemSpec bare = parse(
      "terrain: {file: dem.tif}\nstart: {x: 0, y: 0, heading: 0}\n"
      "goal: {x: 0, y: 0, heading: 0}\n",
      "");
  EXPECT_EQ(*bare.terrain.file, fs::path("dem.tif"));
}

TEST(ProblemLoader, LoadProblemReadsFileAndResolvesAgainstItsFolder) {
  const fs::path dir = fs::path(::testing::TempDir()) / "terratraj_problem_loader_test";
  fs::create_directories(dir / "sub");
  const fs::path file = dir / "sub" / "problem.yaml";
  {
    std::ofstream out(file);
    out << kContractExample;
  }
  const ProblemSpec p = loadProblem(file);
  EXPECT_EQ(p.source_file, file);
  EXPECT_EQ(*p.terrain.file, dir / "sub" / "data" / "dem.tif");
  EXPECT_EQ(*p.vehicle.tables.pitch, dir / "sub" / "tables" / "pitch_vmax.json");

  // An error names the file as given.
  {
    std::ofstream out(file);
    out << "terrain: {generate: {kind: hills}}\nstart: {x: 0, y: 0, heading: 0}\nbogus: 1\n";
  }
  try {
    loadProblem(file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), StartsWith(file.string() + ":3:1: bogus: unknown key"));
  }
  fs::remove_all(dir);
}

TEST(ProblemLoader, EnumNamesRoundTrip) {
  for (const std::string& name : vehicleModelNames()) {
    EXPECT_EQ(vehicleModelName(*parseVehicleModelKind(name)), name);
  }
  for (const std::string& name : costKindNames()) {
    EXPECT_EQ(costKindName(*parseCostKind(name)), name);
  }
  for (const std::string& name : solverMethodNames()) {
    EXPECT_EQ(solverMethodName(*parseSolverMethod(name)), name);
  }
  for (const std::string& name : plannerKindNames()) {
    EXPECT_EQ(plannerKindName(*parsePlannerKind(name)), name);
  }
  EXPECT_EQ(solverMethodNames().size(), 7u);
  EXPECT_FALSE(parseVehicleModelKind("Point").has_value());
  EXPECT_FALSE(parseSolverMethod("").has_value());
  EXPECT_STREQ(vehicleModelName(VehicleModelKind::kFourWheel), "four_wheel");
  EXPECT_STREQ(solverMethodName(SolverMethod::kNewtonFd), "newton_fd");
}

// ---------------------------------------------------------------------------------------------
// Errors: the message format.

TEST(ProblemLoader, ErrorNamesFileLineColumnKeyAndReason) {
  const std::string yaml = R"(terrain:
  generate: {kind: hills}
start: {x: 2.0, y: 3.0, heading_deg: 0}
goal: {x: 6.0, y: 3.0, heading_deg: 0}
vehicle:
  limits:
    v_max:      -1
)";
  EXPECT_EQ(parseError(yaml),
            "problem.yaml:7:17: vehicle.limits.v_max: must be in [0.01, 50] m/s (got -1)");
}

TEST(ProblemLoader, MissingKeyPointsAtParentMap) {
  EXPECT_THAT(parseError("terrain:\n  generate: {rows: 4}\nstart: {x: 0, y: 0, heading: 0}\n"
                         "goal: {x: 0, y: 0, heading: 0}\n"),
              StartsWith("problem.yaml:2:13: terrain.generate.kind: missing required key"));
  EXPECT_THAT(parseError("terrain: {generate: {kind: flat}}\nstart: {x: 0, y: 0, heading: 0}\n"),
              StartsWith("problem.yaml:1:1: goal: missing required key"));
}

// ---------------------------------------------------------------------------------------------
// Errors: unknown keys.

TEST(ProblemLoader, UnknownKeyAtEveryDepth) {
  std::string message = parseError(minimalWith("colour: red\n"));
  EXPECT_THAT(message, HasSubstr("problem.yaml:5:1: colour: unknown key"));
  EXPECT_THAT(message,
              HasSubstr("expected one of: terrain, vehicle, start, goal, cost, solver, planner"));

  message = parseError(minimalWith("vehicle: {limits: {vmax: 1}}\n"));
  EXPECT_THAT(message,
              HasSubstr("vehicle.limits.vmax: unknown key (expected one of: v_max, a_max"));
  EXPECT_THAT(message, HasSubstr("pitch_max_deg"));

  EXPECT_THAT(parseError(withTerrain("{generate: {kind: flat, size: 3}}")),
              HasSubstr("terrain.generate.size: unknown key"));
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, obstacles: {file: b.tif, slope: 3}}")),
              HasSubstr("terrain.obstacles.slope: unknown key"));
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, z: 3}")), HasSubstr("terrain.z: unknown key"));
  EXPECT_THAT(parseError(minimalWith("solver: {tolerance: {position: 1}}\n")),
              HasSubstr("solver.tolerance.position: unknown key (expected one of: position_m, "
                        "heading_rad, lagrangian_gradient)"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {tables: {yaw: t.json}}\n")),
              HasSubstr("vehicle.tables.yaw: unknown key"));
  EXPECT_THAT(parseError(withStart("{x: 0, y: 0, heading: 0, theta: 1}")),
              HasSubstr("start.theta: unknown key"));
  EXPECT_THAT(parseError(minimalWith("cost: {kind: time, beta: 1}\n")),
              HasSubstr("cost.beta: unknown key"));
  EXPECT_THAT(parseError(minimalWith("planner: {kind: prm, timeout: 1}\n")),
              HasSubstr("planner.timeout: unknown key"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {model: point, mass: 3}\n")),
              HasSubstr("vehicle.mass: unknown key"));
}

TEST(ProblemLoader, DuplicateAndNonScalarKeys) {
  EXPECT_THAT(parseError(withStart("{x: 0, x: 1, y: 0, heading: 0}")),
              HasSubstr("start.x: duplicate key"));
  EXPECT_THAT(parseError(minimalWith("? [a, b]\n: 1\n")), HasSubstr("keys must be plain names"));
}

// ---------------------------------------------------------------------------------------------
// Errors: types.

TEST(ProblemLoader, WrongTypes) {
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: abc}}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got \"abc\""));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: {a: 1}}}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got a map"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: [1]}}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got a list"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: \"1.0\"}}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got the quoted string"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: true}}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got \"true\""));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: }}\n")),
              HasSubstr("vehicle.limits.v_max: expected a number, got an empty value"));
  EXPECT_THAT(parseError(minimalWith("vehicle: 3\n")),
              HasSubstr("vehicle: expected a map, got \"3\""));
  EXPECT_THAT(parseError(minimalWith("vehicle:\n")),
              HasSubstr("problem.yaml:5:1: vehicle: expected a map, got an empty value"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: [1, 2]}\n")),
              HasSubstr("vehicle.limits: expected a map, got a list"));
  EXPECT_THAT(parseError(withStart("5")), HasSubstr("start: expected a map, got \"5\""));
  EXPECT_THAT(parseError(withTerrain("{file: [a.tif, b.tif]}")),
              HasSubstr("terrain.file: expected a string, got a list"));
  EXPECT_THAT(parseError(withTerrain("{file: ''}")),
              HasSubstr("terrain.file: expected a file path, got an empty string"));
  EXPECT_THAT(parseError(withTerrain("{generate: hills}")),
              HasSubstr("terrain.generate: expected a map, got \"hills\""));
  EXPECT_THAT(parseError(minimalWith("vehicle: {model: {a: 1}}\n")),
              HasSubstr("vehicle.model: must be one of: point"));
}

TEST(ProblemLoader, IntegersMustBeIntegers) {
  EXPECT_THAT(parseError(withTerrain("{generate: {kind: flat, rows: 2.5}}")),
              HasSubstr("terrain.generate.rows: expected an integer, got 2.5"));
  EXPECT_THAT(parseError(withTerrain("{generate: {kind: flat, cols: abc}}")),
              HasSubstr("terrain.generate.cols: expected an integer, got \"abc\""));
  EXPECT_THAT(parseError(withTerrain("{generate: {kind: flat, seed: 1e3}}")),
              HasSubstr("terrain.generate.seed: expected an integer, got 1e3"));
  EXPECT_THAT(parseError(minimalWith("solver: {intervals: 40.0}\n")),
              HasSubstr("solver.intervals: expected an integer, got 40.0"));
  EXPECT_THAT(parseError(minimalWith("solver: {max_iterations: true}\n")),
              HasSubstr("solver.max_iterations: expected an integer"));
  EXPECT_THAT(parseError(minimalWith("planner: {seed: .nan}\n")),
              HasSubstr("planner.seed: expected an integer"));
  EXPECT_THAT(parseError(minimalWith("planner: {homotopy_classes: 99999999999999999999999}\n")),
              HasSubstr("planner.homotopy_classes: must be <= 1000"));
  EXPECT_THAT(parseError(minimalWith("planner: {seed: 18446744073709551616}\n")),
              HasSubstr("planner.seed: must be <= 18446744073709551615"));
}

TEST(ProblemLoader, NonFiniteNumbersRejected) {
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {v_max: .nan}}\n")),
              HasSubstr("vehicle.limits.v_max: must be a finite number (got .nan)"));
  EXPECT_THAT(parseError(withStart("{x: .inf, y: 0, heading: 0}")),
              HasSubstr("start.x: must be a finite number (got .inf)"));
  EXPECT_THAT(parseError(withStart("{x: 0, y: -.Inf, heading: 0}")),
              HasSubstr("start.y: must be a finite number"));
  EXPECT_THAT(parseError(withStart("{x: 0, y: 0, heading_deg: .NaN}")),
              HasSubstr("start.heading_deg: must be a finite number"));
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, z_scale: 1e999}")),
              HasSubstr("terrain.z_scale: is out of the range of a double"));
}

// ---------------------------------------------------------------------------------------------
// Errors: missing keys, exclusive keys.

TEST(ProblemLoader, MissingRequiredKeys) {
  EXPECT_THAT(parseError("start: {x: 0, y: 0, heading: 0}\ngoal: {x: 0, y: 0, heading: 0}\n"),
              HasSubstr("terrain: missing required key"));
  EXPECT_THAT(parseError("terrain: {generate: {kind: flat}}\ngoal: {x: 0, y: 0, heading: 0}\n"),
              HasSubstr("start: missing required key"));
  EXPECT_THAT(parseError(withStart("{y: 0, heading: 0}")),
              HasSubstr("start.x: missing required key"));
  EXPECT_THAT(parseError(withStart("{x: 0, heading: 0}")),
              HasSubstr("start.y: missing required key"));
  const std::string message = parseError(withStart("{x: 0, y: 0}"));
  EXPECT_THAT(message, HasSubstr("start.heading: missing required key"));
  EXPECT_THAT(message, HasSubstr("heading_deg"));
  EXPECT_THAT(parseError(withTerrain("{generate: {rows: 3}}")),
              HasSubstr("terrain.generate.kind: missing required key"));
}

TEST(ProblemLoader, BothAngleFormsRejected) {
  EXPECT_THAT(parseError(withStart("{x: 0, y: 0, heading: 0, heading_deg: 0}")),
              HasSubstr("start.heading: give either heading or heading_deg, not both"));
  EXPECT_THAT(parseError(minimalWith("vehicle: {limits: {pitch_max: 0.2, pitch_max_deg: 10}}\n")),
              HasSubstr("vehicle.limits.pitch_max: give either pitch_max or pitch_max_deg"));
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, obstacles: {max_slope: 0.2, "
                                     "max_slope_deg: 10}}")),
              HasSubstr("terrain.obstacles.max_slope: give either max_slope or max_slope_deg"));
}

TEST(ProblemLoader, TerrainNeedsExactlyOneOfFileAndGenerate) {
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, generate: {kind: flat}}")),
              HasSubstr("terrain: give either file or generate, not both"));
  EXPECT_THAT(parseError(withTerrain("{frame: local}")),
              HasSubstr("terrain: give one of file (an elevation raster) or generate"));
  EXPECT_THAT(parseError(withTerrain("{}")), HasSubstr("terrain: give one of file"));
}

TEST(ProblemLoader, CellWithGenerateRejected) {
  EXPECT_THAT(parseError(withTerrain("{generate: {kind: flat}, cell: 0.5}")),
              HasSubstr("terrain.cell: not allowed with terrain.generate (set the cell size with "
                        "generate.cell)"));
}

TEST(ProblemLoader, EmptyObstaclesRejected) {
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, obstacles: {}}")),
              HasSubstr("terrain.obstacles: give file, band and/or max_slope_deg"));
}

// ---------------------------------------------------------------------------------------------
// Errors: ranges.

TEST(ProblemLoader, OutOfRangeValues) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {minimalWith("vehicle: {limits: {a_max: 0}}\n"),
       "vehicle.limits.a_max: must be in [0.001, 100] m/s^2 (got 0)"},
      {minimalWith("vehicle: {limits: {omega_max: -2}}\n"),
       "vehicle.limits.omega_max: must be in [0.001, 100] rad/s"},
      {minimalWith("vehicle: {limits: {kappa_max: 0.0}}\n"),
       "vehicle.limits.kappa_max: must be in [0.001, 1000] 1/m"},
      {minimalWith("vehicle: {limits: {sigma_max: -0.1}}\n"),
       "vehicle.limits.sigma_max: must be in [0.0001, 10000] 1/(m s)"},
      {minimalWith("vehicle: {limits: {pitch_max_deg: 95}}\n"),
       "vehicle.limits.pitch_max_deg: must be in (0, 90) deg (got 95)"},
      {minimalWith("vehicle: {limits: {roll_max_deg: 0}}\n"),
       "vehicle.limits.roll_max_deg: must be in (0"},
      {minimalWith("vehicle: {limits: {pitch_max: 2}}\n"),
       "vehicle.limits.pitch_max: must be in (0, 1.5708) rad (got 2)"},
      {minimalWith("cost: {alpha: -1}\n"), "cost.alpha: must be >= 0 (got -1)"},
      {minimalWith("solver: {intervals: 1}\n"), "solver.intervals: must be >= 2 (got 1)"},
      {minimalWith("solver: {intervals: 100001}\n"), "solver.intervals: must be <= 100000"},
      {minimalWith("solver: {max_iterations: 0}\n"), "solver.max_iterations: must be >= 1 (got 0)"},
      {minimalWith("solver: {tolerance: {position_m: 0}}\n"),
       "solver.tolerance.position_m: must be > 0"},
      {minimalWith("solver: {tolerance: {heading_rad: -1}}\n"),
       "solver.tolerance.heading_rad: must be > 0"},
      {minimalWith("solver: {time_limit_s: -0.5}\n"), "solver.time_limit_s: must be >= 0"},
      {minimalWith("planner: {time_limit_s: -1}\n"), "planner.time_limit_s: must be >= 0 (got -1)"},
      {minimalWith("planner: {seed: -1}\n"), "planner.seed: must be >= 0 (got -1)"},
      {minimalWith("planner: {homotopy_classes: 0}\n"), "planner.homotopy_classes: must be >= 1"},
      {minimalWith("planner: {frame_radius_m: 0}\n"), "planner.frame_radius_m: must be > 0"},
      {withTerrain("{generate: {kind: flat, rows: 1}}"),
       "terrain.generate.rows: must be >= 2 (got 1)"},
      {withTerrain("{generate: {kind: flat, cols: -4}}"), "terrain.generate.cols: must be >= 2"},
      {withTerrain("{generate: {kind: flat, cell: 0}}"), "terrain.generate.cell: must be > 0"},
      {withTerrain("{generate: {kind: flat, seed: -3}}"), "terrain.generate.seed: must be >= 0"},
      {withTerrain("{generate: {kind: flat, rows: 65536, cols: 65536}}"),
       "terrain.generate: rows * cols = 65536 * 65536 cells exceeds the limit of 268435456"},
      {withTerrain("{file: a.tif, cell: -0.25}"), "terrain.cell: must be > 0 (got -0.25)"},
      {withTerrain("{file: a.tif, z_scale: 0}"), "terrain.z_scale: must not be 0"},
      {withTerrain("{file: a.tif, obstacles: {max_slope_deg: 90}}"),
       "terrain.obstacles.max_slope_deg: must be in (0, 90) deg (got 90)"},
      {withTerrain("{file: a.tif, obstacles: {max_slope: 0}}"),
       "terrain.obstacles.max_slope: must be in (0, 1.5708) rad"},
      {withStart("{x: 0, y: 0, heading: 0, v: -0.1}"), "start.v: must be >= 0 (got -0.1)"},
  };
  for (const auto& [yaml, expected] : cases) {
    EXPECT_THAT(parseError(yaml), HasSubstr(expected)) << yaml;
  }
  // Zero time limit is allowed.
  EXPECT_DOUBLE_EQ(parse(minimalWith("planner: {time_limit_s: 0}\n")).planner.time_limit_s, 0.0);
}

TEST(ProblemLoader, BoundaryStateWithinVehicleLimits) {
  EXPECT_THAT(parseError(withStart("{x: 0, y: 0, heading: 0, v: 1.5}")),
              HasSubstr("start.v: must be <= vehicle.limits.v_max = 1 m/s (got 1.5)"));
  EXPECT_THAT(parseError("vehicle: {limits: {omega_max: 0.5}}\n" +
                         withStart("{x: 0, y: 0, heading: 0, omega: -0.75}")),
              HasSubstr("start.omega: |omega| must be <= vehicle.limits.omega_max = 0.5 rad/s"));
  EXPECT_THAT(parseError("terrain: {generate: {kind: flat}}\nstart: {x: 0, y: 0, heading: 0}\n"
                         "goal: {x: 0, y: 0, heading: 0, v: 3}\nvehicle: {limits: {v_max: 2}}\n"),
              HasSubstr("goal.v: must be <= vehicle.limits.v_max = 2 m/s (got 3)"));
  // At the limit is fine, whatever the section order.
  const ProblemSpec p = parse(
      "start: {x: 0, y: 0, heading: 0, v: 2, omega: 0.5}\n"
      "vehicle: {limits: {v_max: 2, omega_max: 0.5}}\n"
      "terrain: {generate: {kind: flat}}\ngoal: {x: 0, y: 0, heading: 0}\n");
  EXPECT_DOUBLE_EQ(p.start.v, 2.0);
}

// ---------------------------------------------------------------------------------------------
// Errors: enumerations.

TEST(ProblemLoader, BadEnumValuesListTheOptions) {
  EXPECT_THAT(parseError(minimalWith("vehicle: {model: tank}\n")),
              HasSubstr("vehicle.model: must be one of: point, four_wheel, rocker_bogie, "
                        "segway_rmp (got \"tank\")"));
  std::string kinds;
  for (const std::string& name : terrain::terrainKindNames()) {
    kinds += (kinds.empty() ? "" : ", ") + name;
  }
  EXPECT_THAT(parseError(withTerrain("{generate: {kind: moon}}")),
              HasSubstr("terrain.generate.kind: must be one of: " + kinds + " (got \"moon\")"));
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, frame: utm}")),
              HasSubstr("terrain.frame: must be one of: local, world (got \"utm\")"));
  EXPECT_THAT(parseError(minimalWith("cost: {kind: energy}\n")),
              HasSubstr("cost.kind: must be one of: time, slope_dwell (got \"energy\")"));
  EXPECT_THAT(parseError(minimalWith("solver: {method: gradient}\n")),
              HasSubstr("solver.method: must be one of: auto, newton, newton_fd, ipopt, ceres, "
                        "shooting, collocation (got \"gradient\")"));
  EXPECT_THAT(parseError(minimalWith("planner: {kind: rrt}\n")),
              HasSubstr("planner.kind: must be one of: prm, lattice, taeasl (got \"rrt\")"));
}

// ---------------------------------------------------------------------------------------------
// Errors: the document as a whole.

TEST(ProblemLoader, MalformedYamlReportsLine) {
  const std::string message =
      parseError("terrain: {generate: {kind: flat}}\nstart: [1, 2\ngoal: {x: 0}\n");
  EXPECT_THAT(message, StartsWith("problem.yaml:3:"));
  EXPECT_THAT(message, HasSubstr("invalid YAML"));
  EXPECT_THAT(parseError("terrain:\n  file: a\n file: b\n"), HasSubstr("invalid YAML"));
  EXPECT_THAT(parseError("start: *undefined_anchor\n"), HasSubstr("invalid YAML"));
}

TEST(ProblemLoader, EmptyDocumentRejected) {
  EXPECT_THAT(parseError(""), HasSubstr("problem.yaml: the problem file is empty"));
  EXPECT_THAT(parseError("# nothing but a comment\n"), HasSubstr("the problem file is empty"));
  EXPECT_THAT(parseError("---\n...\n"), HasSubstr("the problem file is empty"));
}

TEST(ProblemLoader, NonMapTopLevelRejected) {
  EXPECT_THAT(parseError("- terrain\n- start\n"),
              HasSubstr("problem.yaml:1:1: the top level must be a map of sections"));
  EXPECT_THAT(parseError("hello"), HasSubstr("the top level must be a map"));
  EXPECT_THAT(parseError(std::string(kMinimal) + "---\nterrain: {}\n"),
              HasSubstr("holds 2 YAML documents; expected one"));
}

TEST(ProblemLoader, LoadProblemMissingFileNamesIt) {
  const fs::path missing = fs::path(::testing::TempDir()) / "no_such_dir" / "missing.yaml";
  try {
    loadProblem(missing);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(missing.string()));
    EXPECT_THAT(error.what(), HasSubstr("no such file"));
  }
  EXPECT_THROW(loadProblem(fs::path(::testing::TempDir())), InputError);
}

TEST(ProblemLoader, OnlyInputErrorEscapesOnOddInput) {
  const std::vector<std::string> odd = {
      "a: &x [*x]\n",
      "terrain: &t {file: a.tif, obstacles: *t}\n",
      "{",
      "\t",
      "terrain: !!binary xyz\n",
      "terrain: {generate: {kind: !custom hills}}\nstart: {x: 0, y: 0, heading: 0}\n",
      std::string(10000, '[') + "\n",
      std::string("terrain: {file: \"\\x00\"}\n"),
      "? !!null\n: 1\n",
      "terrain: {generate: {kind: flat}}\nstart: {x: 0x10, y: 0, heading: 0}\ngoal: {}\n",
  };
  for (const std::string& yaml : odd) {
    EXPECT_THROW(parse(yaml), InputError) << yaml.substr(0, 80);
  }
}

// ---------------------------------------------------------------------------------------------
// resolvePosesOnTerrain.

// A flat 20 x 10 map of 0.5 m cells (10 m x 5 m), its world origin at (1000, 2000).
terrain::ElevationMap smallMap() {
  terrain::GridGeometry geometry;
  geometry.rows = 10;
  geometry.cols = 20;
  geometry.cell = 0.5;
  geometry.world_origin = Eigen::Vector2d(1000.0, 2000.0);
  return terrain::ElevationMap(geometry, 0.0f);
}

ProblemSpec problemAt(double start_x, double start_y, double goal_x, double goal_y,
                      const std::string& frame = "local") {
  const std::string yaml =
      "terrain: {file: dem.tif, frame: " + frame + "}\n" + "start: {x: " + std::to_string(start_x) +
      ", y: " + std::to_string(start_y) + ", heading: 0}\n" +
      "goal: {x: " + std::to_string(goal_x) + ", y: " + std::to_string(goal_y) + ", heading: 0}\n";
  return parseProblem(yaml, "/proj", "problem.yaml");
}

std::string resolveError(ProblemSpec& problem, const terrain::ElevationMap& map) {
  try {
    resolvePosesOnTerrain(problem, map);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(ProblemPoses, LocalPosesInsideAreKept) {
  const terrain::ElevationMap map = smallMap();
  ProblemSpec p = problemAt(1.0, 1.0, 10.0, 5.0);  // the goal on the north-east corner
  resolvePosesOnTerrain(p, map);
  EXPECT_DOUBLE_EQ(p.start.x, 1.0);
  EXPECT_DOUBLE_EQ(p.goal.y, 5.0);
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kLocal);
}

TEST(ProblemPoses, OutsideTheMap) {
  const terrain::ElevationMap map = smallMap();
  ProblemSpec p = problemAt(512.0, 3.0, 1.0, 1.0);
  EXPECT_EQ(resolveError(p, map),
            "problem.yaml: start: (x, y) = (512.0, 3.0) m is outside the map (local extent "
            "[0, 10.0] x [0, 5.0] m)");
  ProblemSpec q = problemAt(1.0, 1.0, 1.0, -0.001);
  EXPECT_THAT(resolveError(q, map), HasSubstr("problem.yaml: goal: (x, y) = (1.0, -0.001) m"));
}

TEST(ProblemPoses, WorldFrameIsConvertedToLocal) {
  const terrain::ElevationMap map = smallMap();
  ProblemSpec p = problemAt(1001.0, 2002.5, 1009.0, 2004.0, "world");
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kWorld);
  resolvePosesOnTerrain(p, map);
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kLocal);
  EXPECT_EQ(p.terrain.frame, terrain::CoordinateFrame::kWorld);
  EXPECT_NEAR(p.start.x, 1.0, kTol);
  EXPECT_NEAR(p.start.y, 2.5, kTol);
  EXPECT_NEAR(p.goal.x, 9.0, kTol);
  EXPECT_NEAR(p.goal.y, 4.0, kTol);
  // A second call does not convert again.
  resolvePosesOnTerrain(p, map);
  EXPECT_NEAR(p.start.x, 1.0, kTol);
}

TEST(ProblemPoses, WorldFrameOutsideLeavesProblemUnchanged) {
  const terrain::ElevationMap map = smallMap();
  ProblemSpec p = problemAt(1001.0, 2001.0, 2.0, 3.0, "world");  // goal given as if local
  const std::string message = resolveError(p, map);
  EXPECT_THAT(message, HasSubstr("problem.yaml: goal: (x, y) = (2.0, 3.0) m (world; local "));
  EXPECT_THAT(message, HasSubstr("is outside the map (world extent [1000.0, 1010.0] x "
                                 "[2000.0, 2005.0] m, local extent [0, 10.0] x [0, 5.0] m)"));
  EXPECT_DOUBLE_EQ(p.start.x, 1001.0);
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kWorld);
}

TEST(ProblemPoses, NoDataCell) {
  terrain::ElevationMap map = smallMap();
  map.elevation()(3, 4) = std::numeric_limits<float>::quiet_NaN();
  ProblemSpec p = problemAt(1.0, 1.0, 2.25, 1.75);  // cell (row 3, col 4)
  EXPECT_THAT(resolveError(p, map),
              HasSubstr("problem.yaml: goal: (x, y) = (2.25, 1.75) m is on a no-data cell "
                        "(row 3, col 4)"));
}

TEST(ProblemPoses, LethalCell) {
  terrain::ElevationMap map = smallMap();
  map.addLayer(terrain::layer_names::kLethal, 0.0f)(2, 2) = 1.0f;
  ProblemSpec p = problemAt(1.25, 1.25, 9.0, 4.0);  // cell (row 2, col 2)
  EXPECT_THAT(resolveError(p, map),
              HasSubstr("problem.yaml: start: (x, y) = (1.25, 1.25) m is on a lethal cell "
                        "(row 2, col 2)"));
}

}  // namespace
}  // namespace terratraj::apps
