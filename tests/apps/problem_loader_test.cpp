// Tests of the problem-file loader (apps/problem_loader.hpp, docs/problem-file.md): valid
// files, and poses resolved on the terrain. Errors: problem_loader_errors_test.cpp.

#include "terratraj/apps/problem_loader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "problem_loader_fixture.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/apps/problem_translation.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/grid_geometry.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

using namespace loader_test;  // NOLINT: the fixture's helpers

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
  EXPECT_EQ(p.solver.time_limit_s, std::optional<double>(kDefaultSolveTimeLimitS));
  EXPECT_EQ(p.planner.kind, PlannerKind::kPrm);
  EXPECT_EQ(p.planner.time_limit_s, std::optional<double>(1.0));
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
  EXPECT_EQ(p.terrain.interpolation, terrain::Interpolation::kCubicBSpline);
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
  EXPECT_EQ(p.solver.time_limit_s, std::optional<double>(kDefaultSolveTimeLimitS));
  EXPECT_EQ(p.planner.kind, PlannerKind::kPrm);
  EXPECT_FALSE(p.planner.time_limit_s.has_value());
  EXPECT_DOUBLE_EQ(planningTimeLimit(p), 1.0);
  EXPECT_EQ(p.planner.seed, 1u);
  EXPECT_EQ(p.planner.homotopy_classes, 3);
  EXPECT_DOUBLE_EQ(p.planner.frame_radius_m, 10.0);
}

TEST(ProblemLoader, GenerateOptionsAndOtherSections) {
  const ProblemSpec p = parse(R"(terrain:
  generate: {kind: dead_end, rows: 10, cols: 20, cell: 0.5, seed: 18446744073709551615}
  z_scale: -2.5
  frame: world
  interpolation: bicubic
  obstacles: {max_slope: 0.5}
vehicle: {model: segway_rmp, limits: {pitch_max: 0.3, roll_max_deg: 45, v_max: 2}}
start: {x: -1e3, y: +3, heading: 1.0, v: 2, omega: -1}
goal: {x: .5, y: 7., heading_deg: 270}
cost: {kind: slope_dwell, alpha: 2.5}
solver: {method: collocation, intervals: 2, max_iterations: 1, time_limit_s: 0.5,
         tolerance: {position_m: 1e-6, heading_rad: 2e-6}, initial_guess: flat,
         transcription_max_iterations: 77, ipopt_max_iterations: 55,
         search_improve_milestones: 0, search_improvements: 5}
planner: {kind: taeasl, time_limit_s: 0, seed: 0, homotopy_classes: 1, frame_radius_m: 2.5}
)");
  const refine::SeededSolveOptions seeded = seededSolveOptions(p, nullptr, nullptr);
  EXPECT_EQ(seeded.search_improve_milestones, 0u);
  EXPECT_EQ(seeded.search_improvements, 5);
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
  EXPECT_EQ(p.terrain.interpolation, terrain::Interpolation::kBicubic);
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
  EXPECT_EQ(p.planner.time_limit_s, std::optional<double>(0.0));
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
// resolvePoses.

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

std::string resolveError(const ProblemSpec& problem, const terrain::ElevationMap& map) {
  try {
    (void)resolvePoses(problem, map);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(ProblemPoses, LocalPosesInsideAreKept) {
  const terrain::ElevationMap map = smallMap();
  const ProblemSpec p = problemAt(1.0, 1.0, 10.0, 5.0);  // the goal on the north-east corner
  const ResolvedPoses poses = resolvePoses(p, map);
  EXPECT_DOUBLE_EQ(poses.start.x, 1.0);
  EXPECT_DOUBLE_EQ(poses.goal.y, 5.0);
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
  const ProblemSpec p = problemAt(1001.0, 2002.5, 1009.0, 2004.0, "world");
  EXPECT_EQ(p.pose_frame, terrain::CoordinateFrame::kWorld);
  const ResolvedPoses poses = resolvePoses(p, map);
  EXPECT_EQ(p.terrain.frame, terrain::CoordinateFrame::kWorld);
  EXPECT_NEAR(poses.start.x, 1.0, kTol);
  EXPECT_NEAR(poses.start.y, 2.5, kTol);
  EXPECT_NEAR(poses.goal.x, 9.0, kTol);
  EXPECT_NEAR(poses.goal.y, 4.0, kTol);
  // The problem keeps its poses as the file gives them: resolving again gives the same.
  EXPECT_DOUBLE_EQ(p.start.x, 1001.0);
  EXPECT_NEAR(resolvePoses(p, map).start.x, 1.0, kTol);
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

// The searches (plan, and the search seed of solve) hold the Segway's speed bound by slope: a
// pitch table never faster than it, 0 where it cannot drive; other vehicles get the problem's own.
TEST(ProblemScene, TheSearchesHoldTheSegwaysSpeedBoundBySlope) {
  const std::string segway = R"(terrain: {generate: {kind: flat, rows: 64, cols: 64, cell: 0.25}}
vehicle: {model: segway_rmp}
start: {x: 2, y: 2, heading: 0}
goal: {x: 12, y: 12, heading: 0}
)";
  std::ostringstream ignore;
  CommandContext context{ignore, ignore, false, std::make_shared<spdlog::logger>("quiet"), nullptr};
  const ProblemSpec problem = parse(segway);
  const ProblemScene scene(problem, context);
  const search::PlanningProblem query = planningProblem(problem, scene);
  ASSERT_NE(query.pitch_table, nullptr);
  EXPECT_EQ(query.pitch_table->lookup(21.0 * kDeg), 0.0);
  EXPECT_EQ(query.pitch_table->lookup(-21.0 * kDeg), 0.0);
  EXPECT_DOUBLE_EQ(query.pitch_table->lookup(0.0), 3.5);
  EXPECT_LE(query.pitch_table->lookup(18.0 * kDeg),
            scene.segwayLookups()->bounds.speedLimit(18.0 * kDeg));

  const ProblemSpec point =
      parse(std::string(segway).replace(segway.find("segway_rmp"), 10, "point"));
  const ProblemScene point_scene(point, context);
  EXPECT_EQ(planningProblem(point, point_scene).pitch_table, nullptr);
}

}  // namespace
}  // namespace terratraj::apps
