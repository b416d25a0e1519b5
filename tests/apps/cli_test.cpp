#include "terratraj/apps/cli.hpp"
#include "cli_run.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {
namespace {

using ::testing::AnyOf;
using ::testing::Eq;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

using testing::run;
using CliResult = testing::CliRun;

std::string sharedData(const std::string& name) {
  return std::string(TERRATRAJ_SHARED_DATA_DIR) + "/" + name;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
  }
  fs::path dir_;
};

TEST_F(CliTest, HelpListsTheCommands) {
  const CliResult r = run({"--help"});
  EXPECT_EQ(r.status, kExitSuccess);
  EXPECT_THAT(r.out, HasSubstr("demo"));
  EXPECT_THAT(r.out, HasSubstr("terrain"));
  const CliResult generate_help = run({"terrain", "generate", "--help"});
  EXPECT_EQ(generate_help.status, kExitSuccess);
  EXPECT_THAT(generate_help.out, HasSubstr("dead_end"));
  EXPECT_THAT(generate_help.out, HasSubstr("--seed"));
}

TEST_F(CliTest, UsageErrorsExitWithStatus2) {
  EXPECT_EQ(run({}).status, kExitBadInput);
  EXPECT_EQ(run({"fly"}).status, kExitBadInput);
  EXPECT_EQ(run({"terrain"}).status, kExitBadInput);
  EXPECT_EQ(run({"terrain", "info"}).status, kExitBadInput);
  const CliResult r = run({"terrain", "generate", "mountains", "--out", path("m.tif"), "--json"});
  EXPECT_EQ(r.status, kExitBadInput);
  EXPECT_THAT(r.err, HasSubstr("mountains"));
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "error");
  EXPECT_THAT(json["error"].get<std::string>(), HasSubstr("mountains"));
}

TEST_F(CliTest, TerrainInfoReportsTheGully) {
  const CliResult r = run({"terrain", "info", sharedData("west_bijou_gully.asc"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);  // exactly one JSON object
  EXPECT_EQ(json["cols"], 43);
  EXPECT_EQ(json["rows"], 89);
  EXPECT_EQ(json["cell_m"], 3.0);
  EXPECT_GT(json["no_data_cells"].get<int>(), 0);
  EXPECT_EQ(json["no_data_cells"].get<int>() + json["valid_cells"].get<int>(), 43 * 89);
  EXPECT_NEAR(json["height_m"]["min"].get<double>(), 1680.8, 0.1);
  EXPECT_NEAR(json["extent_world_m"]["x_min"].get<double>(), 559705.0, 1e-6);
  const CliResult text = run({"terrain", "info", sharedData("west_bijou_gully.asc")});
  EXPECT_EQ(text.status, kExitSuccess);
  EXPECT_THAT(text.out, HasSubstr("43 x 89 cells (cols x rows), cell 3.00 m"));
}

TEST_F(CliTest, TerrainInfoBadFiles) {
  const CliResult missing = run({"terrain", "info", path("nope.tif"), "--json"});
  EXPECT_EQ(missing.status, kExitBadInput);
  EXPECT_THAT(missing.err, HasSubstr("nope.tif: no such file"));
  EXPECT_EQ(nlohmann::json::parse(missing.out)["status"], "error");
  write("garbage.asc", "ncols 3\nnrows 2\ncellsize x\n");
  EXPECT_EQ(run({"terrain", "info", path("garbage.asc")}).status, kExitBadInput);
  const CliResult png = run({"terrain", "info", path("nope.png"), "--cell", "-1"});
  EXPECT_EQ(png.status, kExitBadInput);
}

TEST_F(CliTest, TerrainGenerateWritesEveryKind) {
  for (const std::string& kind : terrain::terrainKindNames()) {
    const std::string file = path(kind + ".tif");
    const CliResult r = run({"terrain", "generate", kind, "--out", file, "--rows", "64", "--cols",
                             "80", "--cell", "0.5", "--seed", "3", "--json"});
    ASSERT_EQ(r.status, kExitSuccess) << kind << ": " << r.err;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["kind"], kind);
    EXPECT_EQ(json["rows"], 64);
    const terrain::ElevationMap map = terrain::loadElevationMap(file);
    EXPECT_EQ(map.geometry().cols, 80);
    EXPECT_DOUBLE_EQ(map.geometry().cell, 0.5);
  }
  EXPECT_EQ(run({"terrain", "generate", "hills", "--out", path("x.tif"), "--rows", "1"}).status,
            kExitBadInput);
  EXPECT_EQ(run({"terrain", "generate", "hills", "--out", path("x.tif"), "--cell", "abc"}).status,
            kExitBadInput);
  write("plain_file", "not a folder");  // a folder cannot be made below a file, even by root
  const CliResult unwritable =
      run({"terrain", "generate", "hills", "--out", path("plain_file/x.tif")});
  EXPECT_EQ(unwritable.status, kExitBadInput);
  EXPECT_THAT(unwritable.err, HasSubstr("plain_file"));
}

TEST_F(CliTest, CheckReadsAProblemAndItsTerrain) {
  write("problem.yaml",
        "terrain:\n  generate: {kind: obstacles, rows: 128, cols: 128, cell: 0.25, seed: 1}\n"
        "vehicle:\n  model: rocker_bogie\n  limits: {v_max: 1.0, pitch_max_deg: 17}\n"
        "start: {x: 3.2, y: 16.0, heading_deg: 0}\n"
        "goal:  {x: 28.8, y: 16.0, heading_deg: 90}\n");
  const CliResult ok = run({"check", path("problem.yaml"), "--json"});
  ASSERT_EQ(ok.status, kExitSuccess) << ok.err;
  const nlohmann::json json = nlohmann::json::parse(ok.out);
  EXPECT_EQ(json["problem"]["vehicle"]["model"], "rocker_bogie");
  EXPECT_NEAR(json["problem"]["goal"]["heading"].get<double>(), M_PI / 2, 1e-12);
  // No solver.time_limit_s: the default wall clock, stated, so that no solve runs forever.
  EXPECT_DOUBLE_EQ(json["problem"]["solver"]["time_limit_s"].get<double>(), 300.0);
  // The surface every solve of the problem uses, stated: the C2 spline unless the file says.
  EXPECT_EQ(json["problem"]["terrain"]["interpolation"], "bspline");
  EXPECT_GT(json["terrain"]["lethal_cells"].get<int>(), 0);
  EXPECT_TRUE(json["start_attitude"]["pitch"].is_number());

  // The rocker-bogie rover cannot rest with its wheels over the map's west edge.
  write("edge.yaml",
        "terrain:\n  generate: {kind: flat, rows: 64, cols: 64, cell: 0.25}\n"
        "vehicle: {model: rocker_bogie}\n"
        "start: {x: 0.1, y: 8.0, heading_deg: 0}\n"
        "goal:  {x: 10.0, y: 8.0, heading_deg: 0}\n");
  const CliResult edge = run({"check", path("edge.yaml")});
  EXPECT_EQ(edge.status, kExitBadInput);
  EXPECT_THAT(edge.err, HasSubstr("start: the rocker_bogie vehicle cannot rest on the terrain"));

  // Look-up tables are read and validated.
  write("pitch.json", R"({"kind": "pitch", "pitch_edges_rad": [0.5, 0.0], "v_max": [1]})");
  write("tables.yaml",
        "terrain:\n  generate: {kind: flat, rows: 64, cols: 64, cell: 0.25}\n"
        "vehicle: {tables: {pitch: pitch.json}}\n"
        "start: {x: 2.0, y: 8.0, heading_deg: 0}\n"
        "goal:  {x: 10.0, y: 8.0, heading_deg: 0}\n");
  const CliResult tables = run({"check", path("tables.yaml")});
  EXPECT_EQ(tables.status, kExitBadInput);
  EXPECT_THAT(tables.err, HasSubstr("pitch.json: pitch_edges_rad: edges must increase strictly"));

  write("off_map.yaml",
        "terrain:\n  generate: {kind: flat, rows: 64, cols: 64, cell: 0.25}\n"
        "start: {x: 3.0, y: 3.0, heading_deg: 0}\n"
        "goal:  {x: 300.0, y: 3.0, heading_deg: 0}\n");
  const CliResult off = run({"check", path("off_map.yaml")});
  EXPECT_EQ(off.status, kExitBadInput);
  EXPECT_THAT(off.err, HasSubstr("goal"));
  EXPECT_THAT(off.err, HasSubstr("outside the map"));

  write("bad_key.yaml",
        "terrain:\n  generate: {kind: flat}\nstart: {x: 1, y: 1, heading: 0}\n"
        "goal: {x: 2, y: 1, heading: 0}\nvehicle:\n  limits: {v_max: -1}\n");
  const CliResult bad = run({"check", path("bad_key.yaml"), "--json"});
  EXPECT_EQ(bad.status, kExitBadInput);
  EXPECT_THAT(bad.err, HasSubstr("vehicle.limits.v_max: must be in [0.01, 50] m/s"));
  EXPECT_THAT(nlohmann::json::parse(bad.out)["error"].get<std::string>(),
              HasSubstr("bad_key.yaml:6"));

  write("terrain_missing.yaml",
        "terrain:\n  file: dem/missing.tif\nstart: {x: 1, y: 1, heading: 0}\n"
        "goal: {x: 2, y: 1, heading: 0}\n");
  const CliResult missing = run({"check", path("terrain_missing.yaml")});
  EXPECT_EQ(missing.status, kExitBadInput);
  EXPECT_THAT(missing.err, HasSubstr("dem/missing.tif: no such file"));
}

TEST_F(CliTest, CheckOnARealDemInWorldCoordinates) {
  write("gully.yaml", "terrain:\n  file: " + sharedData("west_bijou_gully.asc") +
                          "\n  frame: world\nstart: {x: 559727, y: 4380460, heading_deg: 0}\n"
                          "goal: {x: 559765, y: 4380466, heading_deg: 10}\n");
  const CliResult r = run({"check", path("gully.yaml"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_NEAR(json["problem"]["start"]["x"].get<double>(), 22.0, 1e-6);  // now local
  EXPECT_NEAR(json["problem"]["start"]["y"].get<double>(), 240.0, 1e-6);
}

TEST_F(CliTest, LutBuildAndCheckAgreeWithAHandComputation) {
  // A log by hand: pitch 0.1 (bin [0, 0.25)) at speeds 1..200, pitch -0.3 (bin [-0.5, -0.25))
  // at speeds 3 and 4; curvature from omega / v.
  std::ostringstream log;
  log << "t,x,y,roll,pitch,v,omega\n";
  for (int i = 1; i <= 200; ++i) log << i << ",0,0,0.0,0.1," << i << "," << 0.1 * i << "\n";
  log << "201,0,0,0.0,-0.3,3,0\n202,0,0,0.0,-0.3,4,0\n";
  write("drive.csv", log.str());
  const CliResult built =
      run({"lut", "build", "--log", path("drive.csv"), "--out", path("pitch.json"), "--pitch-edges",
           "-0.5,-0.25,0,0.25,0.5", "--json"});
  ASSERT_EQ(built.status, kExitSuccess) << built.err;
  const nlohmann::json report = nlohmann::json::parse(built.out);
  EXPECT_EQ(report["samples"], 202);
  // Bin [0, 0.25): top ceil(0.01 * 200) = 2 speeds, (200 + 199) / 2 = 199.5. Bin [-0.5, -0.25):
  // top ceil(0.02) = 1 speed, 4. The other two bins are empty: 0.
  EXPECT_EQ(report["table"]["v_max"], (std::vector<double>{4.0, 0.0, 199.5, 0.0}));
  std::ifstream written(path("pitch.json"));
  EXPECT_EQ(nlohmann::json::parse(written), report["table"]);

  // A trajectory: 4 states, 1 above its bin's limit (pitch 0.1, v 250 > 199.5), 1 in an empty
  // bin (pitch 0.3, v 1 > 0): 50 %.
  write("traj.csv",
        "t,x,y,roll,pitch,v,curvature\n0,0,0,0,0.1,100,0\n1,1,0,0,0.1,250,0\n"
        "2,2,0,0,-0.3,4,0\n3,3,0,0,0.3,1,0\n");
  const CliResult checked =
      run({"lut", "check", path("traj.csv"), "--table", path("pitch.json"), "--json"});
  ASSERT_EQ(checked.status, kExitSuccess) << checked.err;
  const nlohmann::json check = nlohmann::json::parse(checked.out);
  EXPECT_EQ(check["states"], 4);
  EXPECT_DOUBLE_EQ(check["pitch_violation_fraction"].get<double>(), 0.5);
  EXPECT_TRUE(check["roll_curvature_violation_fraction"].is_null());
  EXPECT_DOUBLE_EQ(check["combined_violation_fraction"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(check["max_excess_mps"].get<double>(), 50.5);
}

TEST_F(CliTest, LutCommandsRejectBadInput) {
  write("no_roll.csv", "t,x,y,pitch,v,curvature\n0,0,0,0,1,0\n");
  write("no_xy.csv", "t,roll,pitch,v,curvature\n0,0,0,1,0\n");
  EXPECT_THAT(run({"lut", "build", "--log", path("no_xy.csv"), "--out", path("t.json")}).err,
              HasSubstr("must name the columns x and y"));
  const CliResult missing =
      run({"lut", "build", "--log", path("no_roll.csv"), "--out", path("t.json")});
  EXPECT_EQ(missing.status, kExitBadInput);
  EXPECT_THAT(missing.err, HasSubstr("needs a 'roll' column"));
  write("log.csv", "t,x,y,roll,pitch,v,curvature\n0,0,0,0,0,1,0\n");
  const CliResult edges = run({"lut", "build", "--log", path("log.csv"), "--out", path("t.json"),
                               "--pitch-edges", "0.2,0.1"});
  EXPECT_EQ(edges.status, kExitBadInput);
  EXPECT_THAT(edges.err, HasSubstr("--pitch-edges: edges must increase strictly"));
  EXPECT_EQ(
      run({"lut", "build", "--log", path("log.csv"), "--out", path("t.json"), "--kind", "yaw"})
          .status,
      kExitBadInput);
  EXPECT_EQ(run({"lut", "build", "--log", path("log.csv"), "--out", path("t.json"), "--pitch-edges",
                 "0:1:x"})
                .status,
            kExitBadInput);
  write("table.json", R"({"kind": "pitch", "pitch_edges_rad": [0, 1], "v_max": [1, 2]})");
  const CliResult bad_table = run({"lut", "check", path("log.csv"), "--table", path("table.json")});
  EXPECT_EQ(bad_table.status, kExitBadInput);
  EXPECT_THAT(bad_table.err, HasSubstr("table.json"));
  EXPECT_EQ(run({"lut", "check", path("log.csv")}).status, kExitBadInput);  // --table required
}

TEST_F(CliTest, LutPhysicsAndSimulatedLog) {
  const CliResult physics =
      run({"lut", "physics", "--out", path("rc.json"), "--kind", "roll_curvature", "--json"});
  ASSERT_EQ(physics.status, kExitSuccess) << physics.err;
  EXPECT_EQ(nlohmann::json::parse(physics.out)["table"]["v_max"].size(), 16u);
  const CliResult simulated =
      run({"lut", "simulate-log", "--out", path("drive.csv"), "--duration", "60", "--json"});
  ASSERT_EQ(simulated.status, kExitSuccess) << simulated.err;
  EXPECT_EQ(nlohmann::json::parse(simulated.out)["samples"], 601);
  const CliResult built =
      run({"lut", "build", "--log", path("drive.csv"), "--out", path("p.json")});
  EXPECT_EQ(built.status, kExitSuccess) << built.err;
  EXPECT_THAT(built.out, HasSubstr("v_max [m/s]"));
}

// `solve`: the contract's report, a CSV whose last row is the goal actually reached, and the
// exit statuses 0 / 1 / 2.
TEST_F(CliTest, SolveWritesTheReportAndTheTrajectory) {
  const std::string problem =
      "terrain:\n  generate: {kind: hill, rows: 64, cols: 64, cell: 0.25, seed: 1}\n"
      "vehicle:\n  model: point\n  limits: {kappa_max: 3.0, sigma_max: 5.0}\n"
      "start: {x: 3.0, y: 6.0, heading_deg: 0, v: 0.5}\n"
      "goal:  {x: 9.0, y: 8.0, heading_deg: 30, v: 0.5}\n";
  write("problem.yaml", problem);
  const CliResult ok =
      run({"solve", path("problem.yaml"), "--json", "--out", path("trajectory.csv")});
  ASSERT_EQ(ok.status, kExitSuccess) << ok.err << ok.out;
  const nlohmann::json json = nlohmann::json::parse(ok.out);
  for (const char* key : {"status", "method", "iterations", "solve_time_ms", "final_time_s", "cost",
                          "length_m", "terminal_error", "max_abs_pitch_rad", "max_abs_roll_rad",
                          "max_speed", "constraint_violation", "history"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["status"], "converged");
  // The default method: auto (global seeds, collocation, the parametric ipopt when collocation
  // fails from a word), which says what it used. Here collocation reaches its iteration limit
  // from the shortest word; ipopt's verified 7.74 s beats collocation's 12.0 s from the next.
  EXPECT_EQ(json["requested_method"], "auto");
  EXPECT_THAT(json["method"].get<std::string>(), AnyOf(Eq("collocation"), Eq("ipopt")));
  EXPECT_LT(json["cost"].get<double>(), 8.0);
  EXPECT_THAT(json["initial_guess"].get<std::string>(), HasSubstr("dubins"));
  EXPECT_LT(json["terminal_error"]["position_m"].get<double>(), 1e-3);
  EXPECT_FALSE(json["history"].empty());
  // The seeds' budgets (the defaults) and each attempt's, printed on stderr as they end.
  EXPECT_DOUBLE_EQ(json["seed_time_s"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(json["first_seed_time_s"].get<double>(), 30.0);
  EXPECT_EQ(json["search_improve_milestones"], 8000);
  EXPECT_EQ(json["search_improvements"], 2);
  ASSERT_FALSE(json["attempts"].empty());
  EXPECT_DOUBLE_EQ(json["attempts"][0]["budget_s"].get<double>(), 30.0);
  EXPECT_EQ(json["attempts"][0]["round"], 0);
  EXPECT_THAT(ok.err, HasSubstr("seed budget 30 s, round 0"));
  std::ifstream csv(path("trajectory.csv"));
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_EQ(header, "t,x,y,z,heading,roll,pitch,v,omega,curvature");
  while (std::getline(csv, line)) last = line;
  std::istringstream row(last);
  std::string t, x, y;
  std::getline(row, t, ',');
  std::getline(row, x, ',');
  std::getline(row, y, ',');
  EXPECT_NEAR(std::stod(x), 9.0, 1e-3);
  EXPECT_NEAR(std::stod(y), 8.0, 1e-3);

  // Rest to rest: solved by default (free speed); newton's linear speed (the paper's
  // parametrisation) cannot move: read but not solved (exit 1, report kept).
  std::string still = problem;
  still.replace(still.find("v: 0.5}\ngoal"), 7, "v: 0.0}");
  still.replace(still.rfind("v: 0.5"), 6, "v: 0.0");
  write("still.yaml", still);
  const CliResult rest = run({"solve", path("still.yaml"), "--json"});
  EXPECT_EQ(rest.status, kExitSuccess) << rest.out;
  const CliResult infeasible = run({"solve", path("still.yaml"), "--method", "newton", "--json"});
  EXPECT_EQ(infeasible.status, kExitNotSolved) << infeasible.out;
  EXPECT_EQ(nlohmann::json::parse(infeasible.out)["status"], "infeasible");

  // Bad input: exit 2 with the key named.
  const CliResult bad_method = run({"solve", path("problem.yaml"), "--method", "magic"});
  EXPECT_EQ(bad_method.status, kExitBadInput);
  write("order.yaml", problem + "solver: {yaw_rate_order: 12}\n");
  const CliResult bad_order = run({"solve", path("order.yaml")});
  EXPECT_EQ(bad_order.status, kExitBadInput);
  EXPECT_THAT(bad_order.err, HasSubstr("solver.yaw_rate_order"));
  write("scheme.yaml", problem + "solver: {method: collocation, scheme: euler}\n");
  const CliResult bad_scheme = run({"solve", path("scheme.yaml"), "--json"});
  EXPECT_EQ(bad_scheme.status, kExitBadInput);
  EXPECT_THAT(bad_scheme.err, HasSubstr("solver.scheme"));
  EXPECT_EQ(nlohmann::json::parse(bad_scheme.out)["status"], "error");
  EXPECT_EQ(run({"solve", path("problem.yaml"), "--guess", path("trajectory.csv")}).status,
            kExitBadInput);  // --guess is for shooting / collocation
  write("offmap.yaml",
        "terrain:\n  generate: {kind: hill, rows: 64, cols: 64, cell: 0.25}\n"
        "start: {x: 3.0, y: 6.0, v: 0.5}\ngoal: {x: 30.0, y: 6.0, v: 0.5}\n");
  EXPECT_EQ(run({"solve", path("offmap.yaml")}).status, kExitBadInput);
}

// `solve` by direct transcription: the contract's report plus Ipopt's status and the active
// constraints; warm start from the parametric solution or from an x,y CSV.
TEST_F(CliTest, SolveByCollocationAndShooting) {
  write("problem.yaml",
        "terrain:\n  generate: {kind: hill, rows: 64, cols: 64, cell: 0.25, seed: 1}\n"
        "vehicle:\n  model: point\n  limits: {v_max: 1.0, a_max: 0.5, kappa_max: 3.0, "
        "sigma_max: 5.0}\n"
        "start: {x: 3.0, y: 6.0, heading_deg: 0, v: 0.0}\n"
        "goal:  {x: 9.0, y: 8.0, heading_deg: 30, v: 0.0}\n"
        "solver: {method: collocation, intervals: 60, control_effort: 0.01, speed_order: 2,\n"
        "         tolerance: {position_m: 0.01, heading_rad: 0.01}}\n");
  const CliResult collocation =
      run({"solve", path("problem.yaml"), "--json", "--out", path("collocation.csv")});
  ASSERT_EQ(collocation.status, kExitSuccess) << collocation.err << collocation.out;
  const nlohmann::json json = nlohmann::json::parse(collocation.out);
  for (const char* key : {"status", "method", "iterations", "solve_time_ms", "final_time_s", "cost",
                          "length_m", "terminal_error", "max_abs_pitch_rad", "max_abs_roll_rad",
                          "max_speed", "constraint_violation", "history", "ipopt_status",
                          "active_constraints", "scheme", "intervals"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["method"], "collocation");
  EXPECT_EQ(json["ipopt_status"], "Solve_Succeeded");
  EXPECT_LT(json["terminal_error"]["position_m"].get<double>(), 0.01);
  // Limits hold at the points; between them (re-simulated) only slightly exceeded.
  EXPECT_LT(json["constraint_violation"].get<double>(), 0.25) << json["violated_limit"];
  // An x,y-only path as the guess, solved by shooting.
  write("path.csv", "x,y\n3,6\n6,6.5\n9,8\n");
  const CliResult shooting = run({"solve", path("problem.yaml"), "--method", "shooting", "--guess",
                                  path("path.csv"), "--json"});
  const nlohmann::json shot = nlohmann::json::parse(shooting.out);
  EXPECT_EQ(shot["method"], "shooting");
  EXPECT_EQ(shot["initial_guess"], path("path.csv"));
  EXPECT_EQ(shooting.status, kExitSuccess) << shooting.out;
  EXPECT_EQ(shot["status"], "converged");
  EXPECT_LT(shot["terminal_error"]["position_m"].get<double>(), 0.01);
  EXPECT_FALSE(shot["ipopt_status"].get<std::string>().empty());
}

// The Segway RMP's CSV carries its platform pitch after the contract's columns (contract,
// Additions), and the report states the solve's time limit: the default when the file sets none.
TEST_F(CliTest, SolveWritesTheSegwaysPlatformPitch) {
  write("segway.yaml",
        "terrain:\n  generate: {kind: hill, rows: 64, cols: 64, cell: 0.25, seed: 1}\n"
        "vehicle:\n  model: segway_rmp\n"
        "start: {x: 3.0, y: 6.0, heading_deg: 0, v: 0.5}\n"
        "goal:  {x: 9.0, y: 7.0, heading_deg: 0, v: 0.5}\n");
  const CliResult ok = run({"solve", path("segway.yaml"), "--json", "--out", path("segway.csv")});
  ASSERT_EQ(ok.status, kExitSuccess) << ok.err << ok.out;
  const nlohmann::json json = nlohmann::json::parse(ok.out);
  EXPECT_DOUBLE_EQ(json["time_limit_s"].get<double>(), 300.0);
  EXPECT_FALSE(json["time_limit_reached"].get<bool>());
  std::ifstream csv(path("segway.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "t,x,y,z,heading,roll,pitch,v,omega,curvature,platform_pitch");
  int rows = 0;
  while (std::getline(csv, line)) {
    const double platform = std::stod(line.substr(line.rfind(',') + 1));
    EXPECT_TRUE(std::isfinite(platform)) << line;  // t, v and pitch are known on every row
    ++rows;
  }
  EXPECT_GT(rows, 10);
}

}  // namespace
}  // namespace terratraj::apps
