// The contract's verdicts (../shared/spec/interface.md, "Verdicts"): one test per trap found by
// the verdict issue, each asserting the corrected status, exit code and message, and property
// tests: whenever a command exits 0, an independent re-check of the CSV it wrote passes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "independent_check.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;
using testing::CliRun;
using testing::independentCheck;
using testing::run;

class VerdictTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj_verdict_" +
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
  // A flat 16 m x 16 m raster (0.25 m cells) with a lethal ring of radius 2 m around (12, 8).
  std::string ringRaster() const {
    terrain::GridGeometry g;
    g.rows = g.cols = 64;
    g.cell = 0.25;
    terrain::ElevationMap map(g);
    terrain::GridLayer& lethal = map.addLayer(terrain::layer_names::kLethal, 0.0f);
    for (int r = 0; r < g.rows; ++r) {
      for (int c = 0; c < g.cols; ++c) {
        const double d = (g.cellCenter({r, c}) - Eigen::Vector2d(12.0, 8.0)).norm();
        if (d > 1.75 && d < 2.3) lethal(r, c) = 1.0f;
      }
    }
    terrain::saveGeoTiff(map, path("ring.tif"));
    return path("ring.tif");
  }
  fs::path dir_;
};

const char* kLimits =
    "vehicle:\n  model: point\n"
    "  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5,\n"
    "           pitch_max_deg: 25, roll_max_deg: 25}\n";

// Trap: collocation and shooting called a straight line through a lethal ring `converged`.
TEST_F(VerdictTest, AGoalInsideALethalRingIsNeverConverged) {
  const std::string yaml = write("ring.yaml", "terrain: {file: " + ringRaster() + "}\n" + kLimits +
                                                  "start: {x: 3, y: 8, heading_deg: 0, v: 0.5}\n"
                                                  "goal: {x: 12, y: 8, heading_deg: 0, v: 0.5}\n");
  for (const char* method : {"collocation", "shooting", "newton", "ipopt"}) {
    SCOPED_TRACE(method);
    const CliRun r = run({"solve", yaml, "--method", method, "--json", "--out", path("t.csv")});
    ASSERT_NE(r.status, kExitBadInput) << r.err;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    if (r.status == kExitSuccess) {
      // Only a trajectory that really avoids the ring may be converged.
      EXPECT_EQ(independentCheck(path("t.csv"), yaml, {}), "");
    } else {
      EXPECT_NE(json["status"], "converged");
      EXPECT_FALSE(json["reason"].get<std::string>().empty());
    }
  }
}

// Trap: what `terrain generate` writes lost its lethal band on the way back in.
TEST_F(VerdictTest, AGeneratedCorridorKeepsItsWalls) {
  const CliRun generated = run({"terrain", "generate", "corridor", "--out", path("c.tif"), "--rows",
                                "128", "--cols", "128", "--seed", "3"});
  ASSERT_EQ(generated.status, kExitSuccess) << generated.err;
  const std::string yaml = write(
      "c.yaml", "terrain: {file: " + path("c.tif") + "}\n" + kLimits +
                    "start: {x: 3, y: 16, heading_deg: 0}\ngoal: {x: 29, y: 16, heading_deg: 0}\n"
                    "planner: {kind: prm, time_limit_s: 0.5, seed: 2}\n");
  const CliRun check = run({"check", yaml, "--json"});
  ASSERT_EQ(check.status, kExitSuccess) << check.err;
  EXPECT_GT(nlohmann::json::parse(check.out)["terrain"]["lethal_cells"].get<int>(), 0);
  const CliRun plan = run({"plan", yaml, "--out-dir", path("out"), "--json"});
  if (plan.status == kExitSuccess) {
    EXPECT_EQ(independentCheck(path("out/solution_0.csv"), yaml, {0.5, 0.35, 0.1}), "");
  }
  // obstacles.file on a raster terratraj wrote reads its lethal band, not its heights.
  const std::string other =
      write("o.yaml",
            "terrain: {generate: {kind: flat, rows: 128, cols: 128, cell: 0.25}, obstacles: "
            "{file: " +
                path("c.tif") +
                "}}\nstart: {x: 3, y: 16, heading_deg: 0}\n"
                "goal: {x: 29, y: 16, heading_deg: 0}\n");
  const CliRun flat = run({"check", other, "--json"});
  ASSERT_EQ(flat.status, kExitSuccess) << flat.err;
  EXPECT_EQ(nlohmann::json::parse(flat.out)["terrain"]["lethal_cells"],
            nlohmann::json::parse(check.out)["terrain"]["lethal_cells"]);
}

// Trap: absurd but finite limits were accepted, then hung or gave 5e-309 s.
TEST_F(VerdictTest, AbsurdLimitsAreRefusedWithTheirRange) {
  for (const char* limit :
       {"v_max: 1.0e-12", "v_max: 1.0e308", "a_max: 1.0e300", "kappa_max: 1.0e-9"}) {
    SCOPED_TRACE(limit);
    const std::string yaml = write(
        "a.yaml", std::string("terrain: {generate: {kind: flat}}\nvehicle: {limits: {") + limit +
                      "}}\nstart: {x: 2, y: 2, heading_deg: 0}\n"
                      "goal: {x: 8, y: 2, heading_deg: 0}\n");
    for (const char* command : {"check", "solve", "plan"}) {
      const CliRun r = run({command, yaml, "--out-dir", path("o")});
      const CliRun r2 = std::string(command) == "plan" ? r : run({command, yaml});
      EXPECT_EQ(r2.status, kExitBadInput) << command;
      EXPECT_THAT(r2.err, HasSubstr("must be in ["));
    }
  }
}

// Trap: `check` said ok where `plan` and `refine` refused (start attitude beyond the limits).
TEST_F(VerdictTest, CheckAppliesTheChecksOfEveryCommand) {
  const std::string source = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/";
  for (const char* example : {"gully_problem.yaml", "solve_problem.yaml", "plan_problem.yaml",
                              "refine_problem.yaml", "lattice_problem.yaml"}) {
    SCOPED_TRACE(example);
    EXPECT_EQ(run({"check", source + example}).status, kExitSuccess);
  }
  const std::string steep =
      write("steep.yaml",
            "terrain: {generate: {kind: ramp, rows: 96, cols: 96, cell: 0.25, seed: 2}}\n"
            "vehicle: {limits: {pitch_max_deg: 0.5, roll_max_deg: 0.5}}\n"
            "start: {x: 2.4, y: 12, heading_deg: 0}\ngoal: {x: 21.6, y: 12, heading_deg: 0}\n");
  std::string message;
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"check", steep}, {"solve", steep}, {"plan", steep, "--out-dir", path("p")}}) {
    const CliRun r = run(args);
    EXPECT_EQ(r.status, kExitBadInput) << args[0];
    EXPECT_THAT(r.err, HasSubstr("beyond vehicle.limits.pitch_max_deg")) << args[0];
    EXPECT_THAT(r.err, HasSubstr("deg")) << args[0];
  }
  // A plan-only rule (the planners cannot turn in place) is refused by check too, naming plan.
  const std::string spin =
      write("spin.yaml",
            "terrain: {generate: {kind: flat}}\nstart: {x: 2, y: 2, heading_deg: 0, omega: "
            "0.5}\ngoal: {x: 8, y: 2, heading_deg: 0}\n");
  const CliRun c = run({"check", spin});
  EXPECT_EQ(c.status, kExitBadInput);
  EXPECT_THAT(c.err, HasSubstr("plan and refine"));
  EXPECT_EQ(run({"plan", spin, "--out-dir", path("q")}).status, kExitBadInput);
}

// Trap: an unwritable output was found only after the computation.
TEST_F(VerdictTest, UnwritableOutputsFailBeforeTheWork) {
  const std::string yaml = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/solve_problem.yaml";
  const auto started = std::chrono::steady_clock::now();
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"solve", yaml, "--out", "/proc/x/t.csv"},
           {"plan", yaml, "--out-dir", "/proc/x"},
           {"plan", yaml, "--out-dir", path("ok"), "--plot", "/proc/x/p.png"},
           {"bench", "tables", "--quick", "--out", "/proc/x/y.json"},
           {"bench", "convergence", "--quick", "--data-dir", path("no-such-folder")}}) {
    const CliRun r = run(args);
    EXPECT_EQ(r.status, kExitBadInput) << args[0] << " " << args.back() << ": " << r.err;
    EXPECT_THAT(r.err, Not(HasSubstr("internal error")));
  }
  // Nothing was computed: these are refusals at once.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
            20.0);
}

// start == goal: one behaviour everywhere (the one-row trajectory, converged / solved); a
// U-turn at the same position is a problem, not "start and goal coincide".
TEST_F(VerdictTest, StartAtTheGoalIsOneBehaviourAcrossCommands) {
  const std::string yaml = write(
      "same.yaml", std::string("terrain: {generate: {kind: hills, rows: 64, cols: 64, cell: 0.25, "
                               "seed: 2}}\n") +
                       kLimits +
                       "start: {x: 8, y: 8, heading_deg: 30}\ngoal: {x: 8, y: 8, "
                       "heading_deg: 30}\nplanner: {time_limit_s: 0.2}\n");
  write("cand.csv", "x,y\n8,8\n9,8\n8,8\n");
  for (const char* method : {"newton", "newton_fd", "ipopt", "ceres", "collocation", "shooting"}) {
    const CliRun r = run({"solve", yaml, "--method", method, "--json", "--out", path("s.csv")});
    ASSERT_EQ(r.status, kExitSuccess) << method << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["status"], "converged");
    EXPECT_EQ(models::readTrajectoryCsv(path("s.csv")).samples.size(), 1u);
  }
  for (const char* planner : {"prm", "lattice", "taeasl"}) {
    const CliRun r = run({"plan", yaml, "--planner", planner, "--out-dir", path("p"), "--json"});
    ASSERT_EQ(r.status, kExitSuccess) << planner << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["status"], "solved");
  }
  const CliRun refine = run({"refine", yaml, "--candidate", path("cand.csv"), "--json"});
  EXPECT_EQ(refine.status, kExitSuccess) << refine.err;
  EXPECT_EQ(run({"check", yaml}).status, kExitSuccess);
  // The same position, heading + 180 deg: solved or not, never refused as coinciding.
  const std::string uturn =
      write("uturn.yaml", std::string("terrain: {generate: {kind: flat, rows: 96, cols: 96, cell: "
                                      "0.25}}\n") +
                              kLimits +
                              "start: {x: 12, y: 12, heading_deg: 0}\ngoal: {x: 12, y: 12, "
                              "heading_deg: 180}\nplanner: {time_limit_s: 0.3}\n");
  for (const char* method : {"newton", "ipopt", "collocation"}) {
    const CliRun r = run({"solve", uturn, "--method", method});
    EXPECT_THAT(r.err, Not(HasSubstr("start and goal coincide"))) << method;
  }
}

// Trap: a candidate 6.7 m from the start was refined to `converged` with a meaningless ratio.
TEST_F(VerdictTest, ACandidateFromElsewhereIsBadInput) {
  const std::string yaml = write(
      "p.yaml", std::string("terrain: {generate: {kind: flat, rows: 96, cols: 96, cell: 0.25}}\n") +
                    kLimits +
                    "start: {x: 2, y: 12, heading_deg: 0}\ngoal: {x: 20, y: 12, "
                    "heading_deg: 0}\n");
  write("far.csv", "x,y\n2,18.7\n11,18\n20,12\n");
  const CliRun r = run({"refine", yaml, "--candidate", path("far.csv")});
  EXPECT_EQ(r.status, kExitBadInput);
  EXPECT_THAT(r.err, HasSubstr("6.7 m from the problem's start"));
  // A bad sample is named by its file line, as the CSV reader does.
  write("nan.csv", "x,y,heading\n2,12,0\n5,12,nan\n20,12,0\n");
  write("off.csv", "x,y\n2,12\n\n50,12\n20,12\n");
  const CliRun off = run({"refine", yaml, "--candidate", path("off.csv")});
  EXPECT_EQ(off.status, kExitBadInput);
  EXPECT_THAT(off.err, HasSubstr("line 4"));
}

// Trap: command-line numbers read differently from the problem file's.
TEST_F(VerdictTest, CommandLineNumbersAreDecimal) {
  const std::string yaml = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/plan_problem.yaml";
  const CliRun seed = run({"plan", yaml, "--seed", "-1", "--out-dir", path("o")});
  EXPECT_EQ(seed.status, kExitBadInput);
  EXPECT_THAT(seed.err, HasSubstr("--seed"));
  const CliRun hex = run({"plan", yaml, "--time-limit", "0x1", "--out-dir", path("o")});
  EXPECT_EQ(hex.status, kExitBadInput);
  EXPECT_THAT(hex.err, HasSubstr("--time-limit"));
  const CliRun typo = run({"frobnicate"});
  EXPECT_EQ(typo.status, kExitBadInput);
  EXPECT_THAT(typo.err, HasSubstr("unknown command 'frobnicate'"));
}

// plan and refine write their report.json (settings, seed, version) beside their CSVs.
TEST_F(VerdictTest, PlanAndRefineWriteTheirReport) {
  const std::string yaml = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/plan_problem.yaml";
  const CliRun plan = run({"plan", yaml, "--out-dir", path("p"), "--time-limit", "0.3"});
  ASSERT_TRUE(fs::exists(path("p/report.json"))) << plan.err;
  std::ifstream in(path("p/report.json"));
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report.contains("version"));
  EXPECT_TRUE(report.contains("seed"));
  EXPECT_TRUE(report.contains("problem"));
}

// Property: over the examples, every command that exits 0 wrote CSVs that pass the
// independent re-check (the solver's own report is not trusted).
TEST_F(VerdictTest, EveryExitZeroWritesATrajectoryThatPassesTheIndependentCheck) {
  const std::string source = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/";
  int checked = 0;
  for (const char* example :
       {"solve_problem.yaml", "collocation_problem.yaml", "hills_problem.yaml"}) {
    const CliRun r = run({"solve", source + example, "--out", path("s.csv")});
    if (r.status != kExitSuccess) continue;
    EXPECT_EQ(independentCheck(path("s.csv"), source + example, {}), "") << example;
    ++checked;
  }
  for (const char* example :
       {"plan_problem.yaml", "lattice_problem.yaml", "taeasl_problem.yaml", "gully_problem.yaml"}) {
    const fs::path out = path(std::string("plan-") + example);
    const CliRun r = run({"plan", source + example, "--out-dir", out.string(), "--json"});
    if (r.status != kExitSuccess) continue;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    ProblemSpec spec = loadProblem(source + example);
    for (const nlohmann::json& s : json["solutions"]) {
      EXPECT_EQ(independentCheck(
                    s["file"].get<std::string>(), source + example,
                    // The examples' lattices are 0.5 m: every planner's default radius is 0.5 m.
                    {spec.planner.goal_position_tolerance_m.value_or(0.5),
                     spec.planner.goal_heading_tolerance, spec.planner.goal_speed_tolerance}),
                "")
          << example;
      ++checked;
    }
  }
  EXPECT_GE(checked, 5);
}

// Property over seeded generated problems: solve (default method), plan and plan --refine.
TEST_F(VerdictTest, SeededGeneratedProblemsNeverExitZeroWithABrokenFile) {
  int checked = 0;
  for (int seed = 1; seed <= 4; ++seed) {
    const char* kind = seed % 2 == 0 ? "forest" : "hills";
    const double gy = 6.0 + 3.0 * seed;
    const std::string yaml = write(
        "g.yaml", std::string("terrain: {generate: {kind: ") + kind +
                      ", rows: 96, cols: 96, cell: 0.25, seed: " + std::to_string(seed) + "}}\n" +
                      kLimits + "start: {x: 2.5, y: 12, heading_deg: 0}\ngoal: {x: 21, y: " +
                      std::to_string(gy) + ", heading_deg: " + std::to_string(20 * seed) +
                      "}\nplanner: {time_limit_s: 0.3, seed: " + std::to_string(seed) + "}\n");
    if (run({"check", yaml}).status != kExitSuccess) continue;  // a pose on an obstacle
    const CliRun solve = run({"solve", yaml, "--out", path("s.csv")});
    if (solve.status == kExitSuccess) {
      EXPECT_EQ(independentCheck(path("s.csv"), yaml, {}), "") << seed;
      ++checked;
    }
    const CliRun plan = run({"plan", yaml, "--refine", "--out-dir", path("p"), "--json"});
    if (plan.status != kExitNotSolved && plan.status != kExitSuccess) {
      ADD_FAILURE() << plan.err;
      continue;
    }
    const nlohmann::json json = nlohmann::json::parse(plan.out);
    for (const nlohmann::json& s : json["solutions"]) {
      EXPECT_EQ(independentCheck(s["file"].get<std::string>(), yaml, {0.5, 0.35, 0.1}), "");
      const nlohmann::json& refined = s["refined"];
      if (refined["status"] == "converged") {
        EXPECT_EQ(independentCheck(refined["file"].get<std::string>(), yaml, {}), "") << seed;
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 3);
}

// Same seed, same files: solve, plan with an iteration budget, a lattice plan.
TEST_F(VerdictTest, SameSeedSameFiles) {
  const std::string source = std::string(TERRATRAJ_SOURCE_DIR) + "/examples/";
  const auto slurp = [](const std::string& file) {
    std::ifstream in(file);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  ASSERT_EQ(run({"solve", source + "solve_problem.yaml", "--out", path("a.csv")}).status,
            kExitSuccess);
  ASSERT_EQ(run({"solve", source + "solve_problem.yaml", "--out", path("b.csv")}).status,
            kExitSuccess);
  EXPECT_EQ(slurp(path("a.csv")), slurp(path("b.csv")));
  const std::string budget =
      write("budget.yaml",
            std::string("terrain: {generate: {kind: hills, rows: 96, cols: 96, cell: 0.25, "
                        "seed: 5}}\n") +
                kLimits +
                "start: {x: 2.5, y: 12, heading_deg: 0}\ngoal: {x: 21, y: 12, "
                "heading_deg: 0}\nplanner: {kind: prm, seed: 7, time_limit_s: "
                "60, max_iterations: 300}\n");
  run({"plan", budget, "--out-dir", path("p1")});
  run({"plan", budget, "--out-dir", path("p2")});
  ASSERT_TRUE(fs::exists(path("p1/solution_0.csv")));
  EXPECT_EQ(slurp(path("p1/solution_0.csv")), slurp(path("p2/solution_0.csv")));
}

}  // namespace
}  // namespace terratraj::apps
