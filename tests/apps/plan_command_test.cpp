// `terratraj plan` and the demo's plan: the contract's report, the CSV, exit statuses.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_translation.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

using testing::CliRun;
using testing::run;

// A 96 x 96 hills map (24 m) and a problem from (2.4, 12) to (21.6, 12).
std::string problemYaml(const std::string& terrain, const std::string& start,
                        const std::string& goal, const std::string& extra = "") {
  return "terrain:\n  " + terrain +
         "\nvehicle:\n  model: point\n"
         "  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5,\n"
         "           pitch_max_deg: 25, roll_max_deg: 25}\n"
         "start: " +
         start + "\ngoal: " + goal + "\nplanner: {kind: prm, time_limit_s: 0.2, seed: 3" + extra +
         "}\n";
}

const char* kHills = "generate: {kind: hills, rows: 96, cols: 96, cell: 0.25, seed: 2}";
const char* kStart = "{x: 2.4, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}";
const char* kGoal = "{x: 21.6, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}";

class PlanCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj_plan_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  CliRun plan(const std::string& yaml, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"plan", write("problem.yaml", yaml), "--out-dir", path("out"),
                                  "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
  fs::path dir_;
};

TEST_F(PlanCommandTest, SolvedReportFollowsTheContract) {
  const CliRun r = plan(problemYaml(kHills, kStart, kGoal));
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  for (const char* key : {"status", "planner", "time_limit_s", "first_solution_ms",
                          "planning_time_ms", "nodes", "trapped_fraction", "solutions", "seed",
                          "cost_history", "best_cost_s", "constraint_violation"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["status"], "solved");
  EXPECT_EQ(json["planner"], "prm");
  EXPECT_DOUBLE_EQ(json["time_limit_s"].get<double>(), 0.2);
  EXPECT_EQ(json["seed"], 3);
  EXPECT_LE(json["first_solution_ms"].get<double>(), json["planning_time_ms"].get<double>());
  EXPECT_NEAR(json["planning_time_ms"].get<double>(), 200.0, 20.0);
  EXPECT_GT(json["nodes"].get<int>(), 1);
  EXPECT_GE(json["trapped_fraction"].get<double>(), 0.0);
  EXPECT_LE(json["trapped_fraction"].get<double>(), 1.0);
  EXPECT_EQ(json["constraint_violation"].get<double>(), 0.0);
  ASSERT_EQ(json["solutions"].size(), 1u);
  const nlohmann::json& solution = json["solutions"][0];
  EXPECT_EQ(solution["homotopy"], "");
  EXPECT_EQ(solution["file"], path("out") + "/solution_0.csv");
  EXPECT_GT(solution["length_m"].get<double>(), 19.2 - 0.5 - 1e-9);  // goal tolerance 0.5 m
  EXPECT_DOUBLE_EQ(solution["cost_s"].get<double>(), json["best_cost_s"].get<double>());
  ASSERT_FALSE(json["cost_history"].empty());
  EXPECT_DOUBLE_EQ(json["cost_history"].back()["cost_s"].get<double>(),
                   solution["cost_s"].get<double>());
  const models::Trajectory t = models::readTrajectoryCsv(solution["file"].get<std::string>());
  for (std::size_t c = 0; c < models::kTrajectoryColumnCount; ++c) EXPECT_TRUE(t.has_column[c]);
  EXPECT_NEAR(t.samples.front().x, 2.4, 1e-9);
  EXPECT_NEAR(t.samples.back().t, solution["cost_s"].get<double>(), 1e-6);
  EXPECT_NEAR(std::hypot(t.samples.back().x - 21.6, t.samples.back().y - 12.0), 0.0, 0.5);

  // Same seed, same options: --seed overrides the file.
  const CliRun other =
      plan(problemYaml(kHills, kStart, kGoal), {"--seed", "9", "--time-limit", "0.1"});
  ASSERT_EQ(other.status, kExitSuccess);
  const nlohmann::json other_json = nlohmann::json::parse(other.out);
  EXPECT_EQ(other_json["seed"], 9);
  EXPECT_DOUBLE_EQ(other_json["time_limit_s"].get<double>(), 0.1);
}

TEST_F(PlanCommandTest, ZeroTimeLimitIsNoSolutionWithExit1) {
  const CliRun r = plan(problemYaml(kHills, kStart, kGoal), {"--time-limit", "0"});
  EXPECT_EQ(r.status, kExitNotSolved);
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "no_solution");
  EXPECT_TRUE(json["first_solution_ms"].is_null());
  EXPECT_TRUE(json["solutions"].empty());
  EXPECT_THAT(json["reason"].get<std::string>(), HasSubstr("0 s"));
}

TEST_F(PlanCommandTest, UnreachableGoalIsNoSolutionWithExit1) {
  // Flat terrain with a lethal ring around the goal (obstacle raster, non-zero = lethal).
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kFlat;
  options.rows = options.cols = 96;
  const terrain::ElevationMap flat = terrain::generateTerrain(options);
  terrain::saveGeoTiff(flat, path("flat.tif"));
  terrain::ElevationMap ring = flat;
  for (int r = 0; r < 96; ++r) {
    for (int c = 0; c < 96; ++c) {
      const int d = std::max(std::abs(r - 48), std::abs(c - 86));
      ring.elevation()(r, c) = d == 5 ? 1.0f : 0.0f;
    }
  }
  terrain::saveGeoTiff(ring, path("ring.tif"));
  const std::string terrain =
      "file: " + path("flat.tif") + "\n  obstacles: {file: " + path("ring.tif") + "}";
  const CliRun r = plan(problemYaml(terrain, kStart, kGoal), {"--time-limit", "0.15"});
  EXPECT_EQ(r.status, kExitNotSolved) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "no_solution");
  EXPECT_THAT(json["reason"].get<std::string>(), HasSubstr("time limit"));
  EXPECT_GT(json["trapped_fraction"].get<double>(), 0.0);
  EXPECT_FALSE(fs::exists(path("out/solution_0.csv")));
}

TEST_F(PlanCommandTest, BadInputsExitWith2AndNameTheCulprit) {
  const auto expectBad = [&](const CliRun& r, const std::string& needle) {
    EXPECT_EQ(r.status, kExitBadInput) << needle << "\n" << r.out << r.err;
    EXPECT_THAT(r.err, HasSubstr(needle));
    const nlohmann::json json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["status"], "error");
  };
  // Off the map.
  expectBad(plan(problemYaml(kHills, "{x: -3.0, y: 12.0, heading_deg: 0}", kGoal)), "start");
  expectBad(plan(problemYaml(kHills, kStart, "{x: 30.0, y: 12.0, heading_deg: 0}")), "goal");
  // On a lethal cell: every cell steeper than 1 degree of the hills is lethal.
  const std::string lethal_hills = std::string(kHills) + "\n  obstacles: {max_slope_deg: 0.5}";
  expectBad(plan(problemYaml(lethal_hills, kStart, kGoal)), "lethal");
  // On a no-data cell.
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kFlat;
  options.rows = options.cols = 96;
  terrain::ElevationMap holed = terrain::generateTerrain(options);
  holed.elevation()(48, 86) = std::numeric_limits<float>::quiet_NaN();
  terrain::saveGeoTiff(holed, path("holed.tif"));
  expectBad(plan(problemYaml("file: " + path("holed.tif"), kStart, kGoal)), "no-data");
  // Outside the limits: the attitude at the start, a speed, turning in place.
  const std::string steep = "generate: {kind: ramp, rows: 96, cols: 96, cell: 0.25, seed: 2}";
  const std::string yaml = problemYaml(steep, kStart, kGoal);
  std::string tight = yaml;
  tight.replace(tight.find("pitch_max_deg: 25, roll_max_deg: 25"), 35,
                "pitch_max_deg: 0.5, roll_max_deg: 0.5");
  expectBad(plan(tight), "beyond vehicle.limits.pitch_max_deg");
  expectBad(plan(problemYaml(kHills, "{x: 2.4, y: 12.0, heading_deg: 0, v: 3.0}", kGoal)), "v_max");
  expectBad(
      plan(problemYaml(kHills, "{x: 2.4, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.5}", kGoal)),
      "start.omega");
  // Planners another issue builds, and bad options.
  expectBad(plan(problemYaml(kHills, kStart, kGoal), {"--planner", "rrt"}), "--planner");
  expectBad(plan(problemYaml(kHills, kStart, kGoal), {"--time-limit=-1"}), "--time-limit");
  expectBad(plan(problemYaml(kHills, kStart, kGoal, ", goal_speed_tolerance: 0")),
            "planner.goal_speed_tolerance");
  expectBad(run({"plan", path("missing.yaml"), "--json"}), "missing.yaml");
}

TEST(PlanProblemKeys, GoalTolerancesAreParsed) {
  const ProblemSpec problem =
      parseProblem(problemYaml(kHills, kStart, kGoal,
                               ", goal_position_tolerance_m: 0.3, goal_heading_tolerance_deg: 10, "
                               "goal_speed_tolerance: 0.05"),
                   ".", "inline.yaml");
  EXPECT_EQ(problem.planner.goal_position_tolerance_m, 0.3);
  EXPECT_NEAR(problem.planner.goal_heading_tolerance, 10.0 * kRadiansPerDegree, 1e-12);
  EXPECT_DOUBLE_EQ(problem.planner.goal_speed_tolerance, 0.05);
  const ProblemSpec defaults = parseProblem(problemYaml(kHills, kStart, kGoal), ".", "inline.yaml");
  EXPECT_FALSE(defaults.planner.goal_position_tolerance_m.has_value());
}

// Absent, the goal region's radius is 0.5 m, and for a lattice at least the distance within
// which every goal has a lattice position: on a 3 m DEM (the gully) its lattice is 3 m and 0.5 m
// held no lattice position (exit 2 with the defaults).
TEST(PlanProblemKeys, TheDefaultGoalRadiusHoldsALatticePosition) {
  ProblemSpec problem = parseProblem(problemYaml(kHills, kStart, kGoal), ".", "inline.yaml");
  terrain::GridGeometry coarse;
  coarse.rows = coarse.cols = 50;
  coarse.cell = 3.0;
  terrain::GridGeometry fine = coarse;
  fine.cell = 0.25;
  EXPECT_DOUBLE_EQ(goalPositionTolerance(problem, coarse), 0.5);  // prm
  for (const PlannerKind kind : {PlannerKind::kLattice, PlannerKind::kTaeasl}) {
    problem.planner.kind = kind;
    EXPECT_DOUBLE_EQ(latticeResolution(problem, coarse), 3.0);
    EXPECT_DOUBLE_EQ(goalPositionTolerance(problem, coarse), 2.13);
    EXPECT_DOUBLE_EQ(goalPositionTolerance(problem, fine), 0.5);
    problem.planner.lattice_resolution_m = 1.0;
    EXPECT_DOUBLE_EQ(goalPositionTolerance(problem, coarse), 0.71);
    problem.planner.lattice_resolution_m.reset();
  }
  problem.planner.goal_position_tolerance_m = 0.3;
  EXPECT_DOUBLE_EQ(goalPositionTolerance(problem, coarse), 0.3);
}

// The lattice planners: one solution (lattice) or one per homotopy class (taeasl), each written,
// re-checked independently and named by its signature.
TEST_F(PlanCommandTest, LatticeAndTaeaslSolveAndReportEverySolution) {
  ::setenv("TERRATRAJ_CACHE_DIR", path("cache").c_str(), 1);
  const CliRun lattice =
      plan(problemYaml(kHills, kStart, kGoal), {"--planner", "lattice", "--time-limit", "2"});
  ASSERT_EQ(lattice.status, 0) << lattice.err << lattice.out;
  const nlohmann::json report = nlohmann::json::parse(lattice.out);
  EXPECT_EQ(report["planner"], "lattice");
  EXPECT_EQ(report["lattice"]["primitives"]["source"], "generated");
  ASSERT_EQ(report["solutions"].size(), 1u);
  EXPECT_EQ(report["solutions"][0]["homotopy"], "");
  EXPECT_TRUE(report["solutions"][0]["check"]["ok"].get<bool>());
  EXPECT_TRUE(fs::exists(path("out/solution_0.csv")));

  // A forest: several classes, distinct signatures; the primitives now come from the cache.
  const std::string forest = "generate: {kind: forest, rows: 128, cols: 128, cell: 0.25, seed: 3}";
  const CliRun taeasl =
      plan(problemYaml(forest, "{x: 3.2, y: 16.0, heading_deg: 0}",
                       "{x: 28.8, y: 16.0, heading_deg: 0}", ", frame_anchor: midpoint"),
           {"--planner", "taeasl", "--time-limit", "5"});
  ASSERT_EQ(taeasl.status, 0) << taeasl.err << taeasl.out;
  const nlohmann::json classes = nlohmann::json::parse(taeasl.out);
  EXPECT_EQ(classes["lattice"]["primitives"]["source"], "cache");
  ASSERT_GE(classes["solutions"].size(), 2u);
  std::vector<std::string> names;
  for (std::size_t k = 0; k < classes["solutions"].size(); ++k) {
    const nlohmann::json& s = classes["solutions"][k];
    EXPECT_TRUE(s["check"]["ok"].get<bool>()) << s.dump();
    EXPECT_TRUE(fs::exists(s["file"].get<std::string>()));
    EXPECT_EQ(std::count(names.begin(), names.end(), s["homotopy"].get<std::string>()), 0);
    names.push_back(s["homotopy"].get<std::string>());
  }
  EXPECT_FALSE(classes["taeasl"]["frames"].empty());
  ::unsetenv("TERRATRAJ_CACHE_DIR");
}

TEST_F(PlanCommandTest, LatticeBadInputsExitWith2) {
  ::setenv("TERRATRAJ_CACHE_DIR", path("cache").c_str(), 1);
  const auto expectBad = [](const CliRun& r, const std::string& what) {
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_THAT(r.err + r.out, HasSubstr(what));
  };
  expectBad(plan(problemYaml(kHills, kStart, kGoal, ", primitives: missing.json"),
                 {"--planner", "lattice"}),
            "missing.json: primitive file not found");
  // A file for another lattice.
  ASSERT_EQ(
      run({"primitives", write("p.yaml", problemYaml(kHills, kStart, kGoal, ", heading_count: 8")),
           "--out", path("eight.json")})
          .status,
      0);
  expectBad(plan(problemYaml(kHills, kStart, kGoal, ", primitives: " + path("eight.json")),
                 {"--planner", "lattice"}),
            "heading_count");
  expectBad(plan(problemYaml(kHills, kStart, kGoal, ", goal_position_tolerance_m: 0.1"),
                 {"--planner", "lattice"}),
            "planner.goal_position_tolerance_m");
  expectBad(
      plan(problemYaml(kHills, kStart, kGoal, ", algorithm: dijkstra"), {"--planner", "lattice"}),
      "planner.algorithm");
  // The start inside an obstacle cluster.
  const std::string forest = "generate: {kind: forest, rows: 128, cols: 128, cell: 0.25, seed: 3}";
  const terrain::ElevationMap map = [] {
    terrain::GeneratorOptions options;
    options.kind = terrain::TerrainKind::kForest;
    options.rows = options.cols = 128;
    options.seed = 3;
    return terrain::generateTerrain(options);
  }();
  const terrain::GridLayer& lethal = *map.findLayer("lethal");
  std::string inside;
  for (int r = 0; r < 128 && inside.empty(); ++r) {
    for (int c = 0; c < 128 && inside.empty(); ++c) {
      if (lethal(r, c) != 0.0f) {
        inside = "{x: " + std::to_string((c + 0.5) * 0.25) +
                 ", y: " + std::to_string((r + 0.5) * 0.25) + ", heading_deg: 0}";
      }
    }
  }
  ASSERT_FALSE(inside.empty());
  expectBad(plan(problemYaml(forest, inside, "{x: 28.8, y: 16.0, heading_deg: 0}"),
                 {"--planner", "taeasl"}),
            "start");
  ::unsetenv("TERRATRAJ_CACHE_DIR");
}

}  // namespace
}  // namespace terratraj::apps
