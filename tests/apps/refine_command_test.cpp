// `terratraj refine`, `plan --refine`, `--plot` and the demo, end to end on small maps: the
// contract's reports, the files, exit statuses, and each refinement checked from its CSV.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "terratraj/apps/cli.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::apps {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

using testing::CliRun;
using testing::run;

// A problem on a generated map of 24 m x 24 m from (2.4, 12) to (21.6, 12), at rest, heading
// east; `extra` is appended as more YAML.
std::string problemYaml(const std::string& kind, const std::string& extra = "") {
  return "terrain:\n  generate: {kind: " + kind +
         ", rows: 96, cols: 96, cell: 0.25, seed: 2}\n"
         "vehicle:\n  model: point\n"
         "  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5,\n"
         "           pitch_max_deg: 25, roll_max_deg: 25}\n"
         "start: {x: 2.4, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}\n"
         "goal:  {x: 21.6, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}\n" +
         extra;
}

// The PNG signature.
bool isPng(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  char header[8] = {};
  in.read(header, 8);
  return in && std::string(header + 1, 3) == "PNG" && fs::file_size(file) > 10000;
}

class RefineCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj_refine_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ::setenv("TERRATRAJ_CACHE_DIR", path("cache").c_str(), 1);
  }
  void TearDown() override {
    ::unsetenv("TERRATRAJ_CACHE_DIR");
    fs::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  fs::path dir_;
};

const std::string kGullyFile = std::string(TERRATRAJ_SHARED_DATA_DIR) + "/west_bijou_gully.asc";

// A point rover beside no data on the gully (3 m cells), 25 deg slopes lethal; `extra` adds
// keys.
std::string gullyYaml(const std::string& extra) {
  return "terrain:\n  file: " + kGullyFile +
         "\n  frame: world\n  obstacles: {max_slope_deg: 25}\n"
         "vehicle: {model: point}\n"
         "start: {x: 559727, y: 4380460, heading_deg: 0}\n"
         "goal:  {x: 559745, y: 4380440, heading_deg: -90}\n" +
         extra;
}

// Checks a refined trajectory from its CSV alone: from the start to the goal, within v_max.
void expectReachesTheGoal(const std::string& csv) {
  const models::Trajectory t = models::readTrajectoryCsv(csv);
  ASSERT_GE(t.samples.size(), 2u);
  EXPECT_NEAR(t.samples.front().x, 2.4, 1e-6);
  EXPECT_NEAR(t.samples.front().y, 12.0, 1e-6);
  EXPECT_NEAR(t.samples.back().x, 21.6, 1e-3);
  EXPECT_NEAR(t.samples.back().y, 12.0, 1e-3);
  for (const models::TrajectorySample& s : t.samples) {
    EXPECT_LE(s.v, 1.0 + 1e-3);
    EXPECT_TRUE(std::isfinite(s.curvature));
  }
}

TEST_F(RefineCommandTest, PlanRefineOnForestKeepsEveryClassAndFollowsTheContract) {
  const std::string problem =
      write("forest.yaml", problemYaml("forest", "planner: {kind: taeasl, time_limit_s: 2.0}\n"));
  const CliRun r = run({"plan", problem, "--refine", "--out-dir", path("out"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "solved");
  ASSERT_GE(json["solutions"].size(), 2u);
  EXPECT_EQ(json["refine"]["candidates"], json["solutions"].size());
  for (const nlohmann::json& s : json["solutions"]) {
    SCOPED_TRACE(s.dump());
    ASSERT_TRUE(s.contains("refined"));
    const nlohmann::json& refined = s["refined"];
    for (const char* key : {"status", "cost_s", "file", "method", "iterations", "homotopy",
                            "homotopy_kept", "max_abs_pitch_rad", "max_abs_roll_rad",
                            "constraint_violation", "cost_ratio", "barrier"}) {
      EXPECT_TRUE(refined.contains(key)) << key;
    }
    EXPECT_EQ(refined["status"], "converged");
    EXPECT_EQ(refined["method"], "collocation");
    EXPECT_EQ(refined["barrier"], "warm");  // TAEASL's routes drive at the limits
    // The class the planner named is the one the refinement started in and kept.
    EXPECT_EQ(s["homotopy_frames"], s["homotopy"]);
    EXPECT_EQ(refined["homotopy"], s["homotopy"]);
    EXPECT_TRUE(refined["homotopy_kept"].get<bool>());
    EXPECT_LE(refined["constraint_violation"].get<double>(), 1e-3);  // the limit tolerance
    EXPECT_TRUE(refined["check"]["ok"].get<bool>());
    EXPECT_TRUE(s.contains("max_abs_pitch_rad"));
    expectReachesTheGoal(refined["file"].get<std::string>());
  }
}

// A coarse lattice (1.5 m) needs a goal region wider than refine's 0.5 m endpoint tolerance:
// its candidate ends 0.75 m short of the goal, and plan --refine takes it from there (it
// refused it before: "not a candidate for this problem").
TEST_F(RefineCommandTest, PlanRefineTakesACoarseLatticesCandidateFromAnywhereInTheGoalRegion) {
  const std::string problem =
      write("coarse.yaml",
            "terrain:\n  generate: {kind: hills, rows: 96, cols: 96, cell: 0.25, seed: 2}\n"
            "vehicle:\n  model: point\n"
            "  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5,\n"
            "           pitch_max_deg: 25, roll_max_deg: 25}\n"
            "start: {x: 2.4, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}\n"
            "goal:  {x: 21.15, y: 12.0, heading_deg: 0, v: 0.0, omega: 0.0}\n"
            "planner: {kind: lattice, time_limit_s: 2.0, lattice_resolution_m: 1.5,\n"
            "          goal_position_tolerance_m: 1.0}\n");
  const CliRun r = run({"plan", problem, "--refine", "--out-dir", path("out"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  ASSERT_GE(json["solutions"].size(), 1u);
  const nlohmann::json& s = json["solutions"][0];
  const models::Trajectory candidate = models::readTrajectoryCsv(s["file"].get<std::string>());
  ASSERT_FALSE(candidate.samples.empty());
  EXPECT_GT(std::hypot(candidate.samples.back().x - 21.15, candidate.samples.back().y - 12.0), 0.5);
  EXPECT_EQ(s["refined"]["status"], "converged") << s["refined"].dump();
  const models::Trajectory refined =
      models::readTrajectoryCsv(s["refined"]["file"].get<std::string>());
  ASSERT_FALSE(refined.samples.empty());
  EXPECT_NEAR(refined.samples.back().x, 21.15, 1e-3);
  EXPECT_NEAR(refined.samples.back().y, 12.0, 1e-3);
}

// No data beside the straight route on a real DEM (the gully's 3 m cells): every Dubins word
// passes where the bicubic surface has no height, so the search seed's route is refined,
// keeping its clearance from the band beside no data. Converged in 0.35 s; an exact no-data
// region in the refiner's clearance (tried, reverted) stalled it at 500 iterations. The
// search's budget is planner.time_limit_s (its first solution ends it).
TEST_F(RefineCommandTest, SolveBesideNoDataOnTheGullyConverges) {
  const std::string problem =
      write("gully.yaml", gullyYaml("solver: {time_limit_s: 120}\nplanner: {time_limit_s: 20}\n"));
  const CliRun r = run({"solve", problem, "--out", path("t.csv"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "converged") << json["reason"];
  EXPECT_TRUE(json["check"]["ok"].get<bool>());
  EXPECT_THAT(json["initial_guess"].get<std::string>(), HasSubstr("search"));
  EXPECT_LT(json["iterations"].get<int>(), 300);
}

// Beside no data the surface is undefined within a few cells (3 m each on the gully): the PRM
// checks the vehicle's placement along the chords between its samples there, so every point
// between two rows of its route is on the terrain (a transcription's guess interpolates them;
// before 2026-12-07 a refinement of this route failed with "the rover cannot be placed").
TEST_F(RefineCommandTest, ThePrmsRouteBesideNoDataIsOnTheTerrainBetweenItsRows) {
  const std::string problem =
      write("gully.yaml",
            gullyYaml("planner: {kind: prm, time_limit_s: 60, max_iterations: 9000, seed: 1}\n"));
  const CliRun r = run({"plan", problem, "--out-dir", path("prm"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const terrain::ElevationMap map = terrain::loadElevationMap(kGullyFile);
  const terrain::TerrainSurface surface(map, terrain::kDefaultInterpolation);
  const models::Trajectory route = models::readTrajectoryCsv(path("prm/solution_0.csv"));
  ASSERT_GE(route.samples.size(), 2u);
  int checked = 0;
  for (std::size_t i = 1; i < route.samples.size(); ++i) {
    const Eigen::Vector2d a(route.samples[i - 1].x, route.samples[i - 1].y);
    const Eigen::Vector2d b(route.samples[i].x, route.samples[i].y);
    const int steps = static_cast<int>(std::ceil((b - a).norm() / 0.01));
    for (int j = 0; j <= steps; ++j, ++checked) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(j) / std::max(steps, 1));
      ASSERT_TRUE(surface.height(p).has_value()) << "no terrain at (" << p.x() << ", " << p.y()
                                                 << ") between rows " << i << " and " << i + 1;
    }
  }
  EXPECT_GT(checked, 1000);
}

// The PRM's route on the gully (seed 1) runs 5 cm from where the surface ends beside no data
// (columns t, x, y, z, heading, roll, pitch, v, omega, curvature).
const std::vector<std::array<double, 10>> kGullyRoute = {
    {0.000000, 22.000000, 240.000000, 1724.640880, 0.000000, -0.008825, -0.004354, 0.000000,
     0.000000, 0.000000},
    {1.771844, 22.784850, 240.000000, 1724.637224, 0.000000, -0.006882, -0.005080, 0.885922,
     0.000000, 0.000000},
    {3.119499, 24.055620, 240.000000, 1724.630255, 0.000000, -0.002284, -0.005640, 1.000000,
     0.000000, 0.000000},
    {4.619499, 25.539761, 239.838569, 1724.622016, -0.325359, 0.001748, -0.005738, 1.000000,
     -0.433808, -0.433808},
    {6.119499, 26.818398, 239.067982, 1724.612537, -0.650721, 0.001729, -0.005881, 1.000000,
     -0.000000, -0.000000},
    {7.619499, 28.011849, 238.159358, 1724.608229, -0.650721, -0.001664, 0.000779, 1.000000,
     0.000000, 0.000000},
    {9.119499, 29.205319, 237.250718, 1724.613231, -0.650721, -0.004737, 0.004738, 1.000000,
     0.000000, 0.000000},
    {10.619499, 30.398777, 236.342089, 1724.619680, -0.650721, -0.005080, 0.003462, 1.000000,
     0.000000, 0.000000},
    {12.119499, 31.592241, 235.433454, 1724.624291, -0.650721, -0.003670, 0.003346, 1.000000,
     0.000000, 0.000000},
    {13.619499, 32.785706, 234.524820, 1724.629717, -0.650721, -0.001230, 0.003221, 1.000000,
     0.000000, 0.000000},
    {15.119499, 33.901824, 233.528221, 1724.631472, -0.885342, 0.001875, -0.001970, 1.000000,
     -0.312827, -0.312827},
    {16.619499, 34.656966, 232.236440, 1724.621462, -1.119962, 0.001130, -0.011442, 1.000000,
     -0.000000, -0.000000},
    {18.119499, 35.310498, 230.886402, 1724.599186, -1.119962, -0.000998, -0.017374, 1.000000,
     0.000000, 0.000000},
    {19.619499, 35.963974, 229.536480, 1724.571723, -1.119962, -0.006319, -0.018599, 1.000000,
     0.000000, 0.000000},
    {20.382486, 36.296362, 228.849846, 1724.557377, -1.119962, -0.009951, -0.019417, 1.000000,
     0.000000, 0.000000},
    {21.882486, 36.949814, 227.499975, 1724.522582, -1.119962, -0.017203, -0.028879, 1.000000,
     0.000000, 0.000000},
    {22.728654, 37.318349, 226.738670, 1724.493733, -1.119962, -0.022711, -0.040212, 1.000000,
     0.000000, 0.000000},
    {24.228654, 37.946755, 225.378173, 1724.411251, -1.174361, -0.045952, -0.070873, 1.000000,
     -0.072495, -0.072495},
    {25.728654, 38.474028, 223.977942, 1724.280817, -1.228802, -0.088262, -0.102969, 1.000000,
     -0.000000, -0.000000},
    {27.228654, 38.974413, 222.572295, 1724.105225, -1.228802, -0.133357, -0.130228, 1.000000,
     0.000000, 0.000000},
    {28.797683, 39.473203, 221.171130, 1723.891225, -1.228802, -0.180153, -0.156061, 0.912012,
     0.000000, 0.000000},
    {30.621706, 39.748760, 220.397057, 1723.755067, -1.228802, -0.208519, -0.172793, 0.000000,
     0.000000, 0.000000}};

// The refiner keeps clear of where the surface is undefined beside no data, measured exactly
// (terrain::ClearanceMap), no farther: the refinement of the route above is faster than the
// route. (Before 2026-12-07 the clearance kept half a cell, 1.5 m here, more than the route did,
// and the refinement was worse: 31.56 s.) From the path alone (x, y, heading) the first solve
// leaves the terrain between two points; the re-simulation says so at once (it used to grind
// through a million CVODES steps), and a second round keeps the clearance floor.
TEST_F(RefineCommandTest, RefinesTheGullyRouteBesideNoDataIntoAFasterTrajectory) {
  const std::string problem = write("gully.yaml", gullyYaml(""));
  std::string full = "t,x,y,z,heading,roll,pitch,v,omega,curvature\n", path_only = "x,y,heading\n";
  for (const std::array<double, 10>& row : kGullyRoute) {
    for (std::size_t k = 0; k < row.size(); ++k) full += (k ? "," : "") + std::to_string(row[k]);
    full += "\n";
    path_only +=
        std::to_string(row[1]) + "," + std::to_string(row[2]) + "," + std::to_string(row[4]) + "\n";
  }
  const terrain::ElevationMap map = terrain::loadElevationMap(kGullyFile);
  const terrain::TerrainSurface surface(map, terrain::kDefaultInterpolation);
  for (const auto& [name, text] :
       {std::pair{"route.csv", full}, std::pair{"path.csv", path_only}}) {
    SCOPED_TRACE(name);
    const std::string candidate = write(name, text);
    const std::string out = path(std::string("refined-") + name);
    const CliRun r = run({"refine", problem, "--candidate", candidate, "--out", out, "--json"});
    ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["status"], "converged") << json["reason"];
    EXPECT_LT(json["cost"].get<double>(), json["candidate"]["cost"].get<double>());
    const models::Trajectory refined = models::readTrajectoryCsv(out);
    for (const models::TrajectorySample& s : refined.samples) {
      ASSERT_TRUE(surface.height({s.x, s.y}).has_value()) << s.x << ", " << s.y;
    }
  }
}

// The PRM's route after 0.5 s is already near the fastest: its refinement converges, reaches the
// goal itself, and costs at most about the time the route saved by stopping in the goal region
// (up to 0.5 m short, at up to 0.1 m/s): 1 s.
TEST_F(RefineCommandTest, PlanRefineWithThePrmOnHillsAndCorridorConvergesToTheGoal) {
  for (const char* kind : {"hills", "corridor"}) {
    SCOPED_TRACE(kind);
    const std::string problem =
        write(std::string(kind) + ".yaml",
              problemYaml(kind, "planner: {kind: prm, time_limit_s: 0.5, seed: 4}\n"));
    const CliRun r = run({"plan", problem, "--refine", "--out-dir", path(kind), "--json"});
    ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    const nlohmann::json& refined = json["solutions"][0]["refined"];
    EXPECT_EQ(refined["status"], "converged") << refined.dump();
    EXPECT_LT(refined["cost_s"].get<double>(), json["solutions"][0]["cost_s"].get<double>() + 1.0);
    expectReachesTheGoal(refined["file"].get<std::string>());
  }
}

TEST_F(RefineCommandTest, RefinesAnXyPathAndReportsBothSides) {
  const std::string problem = write("hills.yaml", problemYaml("hills"));
  const std::string candidate = write("path.csv", "x,y\n2.4,12\n8,14.5\n14,14.5\n21.6,12\n");
  const CliRun r = run({"refine", problem, "--candidate", candidate, "--out", path("r.csv"),
                        "--plot", path("plots/refine.png"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err << r.out;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  for (const char* key : {"status", "method", "iterations", "solve_time_ms", "final_time_s", "cost",
                          "length_m", "terminal_error", "max_abs_pitch_rad", "max_abs_roll_rad",
                          "max_speed", "constraint_violation", "history"}) {
    EXPECT_TRUE(json.contains(key)) << key;  // the contract's solve / refine report
  }
  EXPECT_EQ(json["status"], "converged");
  EXPECT_LT(json["terminal_error"]["position_m"].get<double>(), 1e-3);
  EXPECT_FALSE(json["history"].empty());
  const nlohmann::json& before = json["candidate"];
  EXPECT_EQ(before["file"], candidate);
  EXPECT_THAT(before["derived_columns"].dump(), HasSubstr("\"t\""));
  EXPECT_GT(before["cost"].get<double>(), json["cost"].get<double>());
  EXPECT_LT(json["cost_ratio"].get<double>(), 1.0);
  EXPECT_TRUE(json["homotopy"]["kept"].get<bool>());
  EXPECT_EQ(json["file"], path("r.csv"));
  expectReachesTheGoal(path("r.csv"));
  ASSERT_EQ(json["plots"]["status"], "ok") << json["plots"].dump();
  EXPECT_TRUE(isPng(path("plots/refine.png")));
  EXPECT_TRUE(isPng(path("plots/refine-profiles.png")));
  EXPECT_TRUE(isPng(path("plots/refine-convergence.png")));

  // Text mode: candidate beside refinement.
  const CliRun text = run({"refine", problem, "--candidate", candidate});
  EXPECT_EQ(text.status, kExitSuccess);
  EXPECT_THAT(text.out, HasSubstr("candidate"));
  EXPECT_THAT(text.out, HasSubstr("refined"));
}

TEST_F(RefineCommandTest, UnusableCandidatesExit2WithTheReport) {
  const std::string problem = write("hills.yaml", problemYaml("hills"));
  struct Case {
    const char* csv;
    const char* message;
  };
  for (const Case& c : {Case{"x,y\n2.4,12\n", "single point"},
                        Case{"x,y\n2.4,12\n12,40\n21.6,12\n", "leaves the map"},
                        Case{"x,y\n2.4,12\nnan,12\n21.6,12\n", "not a finite number"}}) {
    SCOPED_TRACE(c.csv);
    const std::string candidate = write("bad.csv", c.csv);
    const CliRun r = run({"refine", problem, "--candidate", candidate, "--json"});
    EXPECT_EQ(r.status, kExitBadInput);
    EXPECT_THAT(r.err, HasSubstr("bad.csv"));
    EXPECT_THAT(r.err, HasSubstr(c.message));
    const nlohmann::json json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["status"], "error");
    EXPECT_THAT(json["error"].get<std::string>(), HasSubstr(c.message));
  }
  // No such file, no x column, a file that is not CSV.
  EXPECT_EQ(run({"refine", problem, "--candidate", path("missing.csv")}).status, kExitBadInput);
  EXPECT_EQ(run({"refine", problem, "--candidate", write("noxy.csv", "t,v\n0,0\n1,1\n")}).status,
            kExitBadInput);
  EXPECT_EQ(run({"refine", problem}).status, kExitBadInput);  // --candidate is required
  EXPECT_EQ(run({"refine", problem, "--candidate", write("ok.csv", "x,y\n2.4,12\n21.6,12\n"),
                 "--method", "magic"})
                .status,
            kExitBadInput);
}

TEST_F(RefineCommandTest, AFailedRefinementStillReportsTheCandidateAndExits1) {
  const std::string problem = write(
      "hills.yaml", problemYaml("hills", "refine: {method: collocation, max_iterations: 1}\n"));
  const std::string candidate = write("path.csv", "x,y\n2.4,12\n8,14.5\n14,14.5\n21.6,12\n");
  const CliRun r = run({"refine", problem, "--candidate", candidate, "--json"});
  EXPECT_EQ(r.status, kExitNotSolved) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "max_iterations");
  EXPECT_FALSE(json["reason"].get<std::string>().empty());
  EXPECT_EQ(json["max_iterations"], 1);
  EXPECT_TRUE(json["candidate"]["cost"].is_number());
}

TEST_F(RefineCommandTest, BadRefineKeysNameTheKey) {
  for (const auto& [yaml, key] : std::vector<std::pair<std::string, std::string>>{
           {"refine: {methd: auto}\n", "methd"},
           {"refine: {method: magic}\n", "refine.method"},
           {"refine: {limit_margin: 0.7}\n", "refine.limit_margin"},
           {"refine: {interval_length_m: -1}\n", "refine.interval_length_m"},
           {"refine: {min_intervals: 50, max_intervals: 10}\n", "refine.max_intervals"},
           {"refine: {warm_start_time_ratio: 0.5}\n", "refine.warm_start_time_ratio"},
           {"refine: {time_limit_s: .nan}\n", "refine.time_limit_s"}}) {
    SCOPED_TRACE(yaml);
    const std::string problem = write("bad.yaml", problemYaml("hills", yaml));
    const CliRun r = run({"plan", problem, "--refine", "--out-dir", path("out")});
    EXPECT_EQ(r.status, kExitBadInput);
    EXPECT_THAT(r.err, HasSubstr(key));
  }
}

TEST_F(RefineCommandTest, DemoPlansRefinesAndPlots) {
  const CliRun r =
      run({"demo", "--out-dir", path("demo"), "--rows", "96", "--cols", "96", "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["status"], "solved");
  EXPECT_EQ(json["planner"], "taeasl");
  EXPECT_EQ(terrain::loadElevationMap(path("demo/terrain.tif")).geometry().rows, 96);
  std::ifstream report(path("demo/report.json"));
  EXPECT_EQ(nlohmann::json::parse(report), json);
  ASSERT_GE(json["solutions"].size(), 2u);
  for (const nlohmann::json& s : json["solutions"]) {
    EXPECT_TRUE(fs::exists(s["file"].get<std::string>()));
    EXPECT_EQ(s["refined"]["status"], "converged") << s["refined"].dump();
    EXPECT_TRUE(fs::exists(s["refined"]["file"].get<std::string>()));
  }
  ASSERT_EQ(json["plots"]["status"], "ok") << json["plots"].dump();
  for (const char* png : {"demo/plot.png", "demo/plot-profiles.png", "demo/plot-convergence.png"}) {
    EXPECT_TRUE(isPng(path(png))) << png;
  }
  // A person reads the text summary.
  const CliRun text =
      run({"demo", "--out-dir", path("demo2"), "--rows", "96", "--cols", "96", "--no-plot"});
  ASSERT_EQ(text.status, kExitSuccess) << text.err;
  EXPECT_THAT(text.out, HasSubstr("refined"));
  EXPECT_THAT(text.out, HasSubstr("class"));
  EXPECT_FALSE(fs::exists(path("demo2/plot.png")));
}

TEST_F(RefineCommandTest, SolvePlotsItsTrajectory) {
  const std::string problem =
      write("solve.yaml",
            "terrain:\n  generate: {kind: hills, rows: 96, cols: 96, cell: 0.25, seed: 2}\n"
            "vehicle: {model: point}\n"
            "start: {x: 6.0, y: 12.0, heading_deg: 0, v: 0.5}\n"
            "goal:  {x: 11.0, y: 13.0, heading_deg: 20, v: 0.5}\n");
  const CliRun r = run({"solve", problem, "--plot", path("solve.png"), "--json"});
  ASSERT_EQ(r.status, kExitSuccess) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  ASSERT_EQ(json["plots"]["status"], "ok") << json["plots"].dump();
  EXPECT_TRUE(isPng(path("solve.png")));
  EXPECT_TRUE(isPng(path("solve-profiles.png")));
  EXPECT_TRUE(isPng(path("solve-convergence.png")));
  EXPECT_TRUE(fs::exists(path("solve-trajectory.csv")));
}

TEST_F(RefineCommandTest, PlotWithoutMatplotlibIsAWarningNotACrash) {
  ::setenv("TERRATRAJ_PYTHON", "/nonexistent/python3", 1);
  const std::string problem = write("hills.yaml", problemYaml("hills"));
  const std::string candidate = write("path.csv", "x,y\n2.4,12\n21.6,12\n");
  const CliRun r =
      run({"refine", problem, "--candidate", candidate, "--plot", path("p.png"), "--json"});
  ::unsetenv("TERRATRAJ_PYTHON");
  EXPECT_EQ(r.status, kExitSuccess) << r.err;
  const nlohmann::json json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["plots"]["status"], "error");
  EXPECT_THAT(json["plots"]["error"].get<std::string>(), HasSubstr("/nonexistent/python3"));
  EXPECT_THAT(r.err, HasSubstr("--plot"));
}

}  // namespace
}  // namespace terratraj::apps
