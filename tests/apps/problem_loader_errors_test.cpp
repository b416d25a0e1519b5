// Tests of the problem-file loader's errors (apps/problem_loader.hpp, docs/problem-file.md):
// every message names file, line, column, key and reason.

#include "terratraj/apps/problem_loader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "problem_loader_fixture.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/grid_geometry.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

using namespace loader_test;  // NOLINT: the fixture's helpers

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
      {minimalWith("solver: {seed_time_s: 0}\n"), "solver.seed_time_s: must be > 0 (got 0)"},
      {minimalWith("solver: {first_seed_time_s: -3}\n"),
       "solver.first_seed_time_s: must be > 0 (got -3)"},
      {minimalWith("solver: {search_improve_milestones: -1}\n"),
       "solver.search_improve_milestones: must be >= 0 (got -1)"},
      {minimalWith("solver: {search_improvements: 1.5}\n"), "solver.search_improvements:"},
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
  EXPECT_EQ(parse(minimalWith("planner: {time_limit_s: 0}\n")).planner.time_limit_s,
            std::optional<double>(0.0));
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
  // Only the surfaces smooth enough to optimise on.
  EXPECT_THAT(parseError(withTerrain("{file: a.tif, interpolation: bilinear}")),
              HasSubstr("terrain.interpolation: must be one of: bspline, bicubic (got "
                        "\"bilinear\")"));
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

}  // namespace
}  // namespace terratraj::apps
