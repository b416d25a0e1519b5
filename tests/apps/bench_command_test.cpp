// `terratraj bench`: the suites' rows and summaries, shards and their merge, worker processes,
// figures, and bad input.

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "terratraj/apps/bench_command.hpp"
#include "terratraj/apps/cli.hpp"
#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
using bench::distributionJson;
using bench::figureText;

namespace {

namespace fs = std::filesystem;
using testing::run;

class BenchCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj-bench-test-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static nlohmann::json read(const std::string& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  }
  static std::set<std::string> ids(const nlohmann::json& result) {
    std::set<std::string> out;
    for (const nlohmann::json& row : result["rows"]) out.insert(row["id"].get<std::string>());
    return out;
  }
  fs::path dir_;
};

// Four parametric solvers on the first problem of the flat fan: every row converged by the
// independent re-simulation, the summary and the run's provenance are there.
TEST_F(BenchCommandTest, ConvergenceRowsAreReSimulatedResults) {
  const testing::CliRun r = run({"bench", "convergence", "--quick", "--data-dir", "", "--cases",
                                 "0,1,2,3,4,5", "--out", path("c.json"), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json result = read(path("c.json"));
  EXPECT_EQ(result["suite"], "convergence");
  // No DEM problems without a data dir; the robustness set's flat turns and turn-backs.
  EXPECT_EQ(result["cases_total"], (5 + 6 + 3) * 7 + (4 + 2) * 5);
  ASSERT_EQ(result["rows"].size(), 6u);
  std::set<std::string> solvers;
  for (const nlohmann::json& row : result["rows"]) {
    EXPECT_EQ(row["set"], "flat_fan");
    EXPECT_EQ(row["problem"], 0);
    solvers.insert(row["solver"].get<std::string>());
    if (row["formulation"] == "parametric") {
      EXPECT_EQ(row["status"], "converged") << row.dump();
      EXPECT_LT(row["terminal_error_m"].get<double>(), 1e-3);
      EXPECT_NEAR(row["cost"].get<double>(), 10.0, 0.6);  // 5 m at 0.5 m/s, a gentle curve
    }
    EXPECT_GT(row["time_ms"].get<double>(), 0.0);
  }
  EXPECT_EQ(solvers.size(), 6u);
  // The four parametric solvers reach the same optimum: each is within 0.1 % of the best.
  for (const char* solver : {"newton_fd", "newton", "ipopt", "ceres"}) {
    const nlohmann::json& s = result["summary"]["solvers"][solver];
    EXPECT_EQ(s["converged"], 1) << solver;
    EXPECT_LT(s["cost_relative_to_best"]["max"].get<double>(), 1.001) << solver;
  }
  EXPECT_TRUE(result["machine"].contains("commit"));
  EXPECT_GE(result["machine"]["cores"].get<int>(), 1);
  EXPECT_EQ(result["settings"]["quick"], true);
  EXPECT_EQ(result["settings"]["interpolation"], "bspline");  // every command's surface
  EXPECT_NE(r.err.find("[6/6] flat_fan/0/collocation"), std::string::npos) << r.err;
}

// The refine suite: each refinement's time, Ipopt iterations and barrier, and the summary's
// time and iteration distributions (issue 17's 100 ms target is read from them).
TEST_F(BenchCommandTest, RefineRowsAndSummaryGiveTimesAndIterations) {
  const testing::CliRun r = run({"bench", "refine", "--quick", "--cases", "0", "--out",
                                 path("r.json"), "--json"});  // the PRM's first, quick hills
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json result = read(path("r.json"));
  ASSERT_EQ(result["rows"].size(), 1u);
  const nlohmann::json& row = result["rows"][0];
  EXPECT_EQ(row["planner"], "prm_first");
  ASSERT_GE(row["candidates"].size(), 1u);
  int count = 0;
  for (const nlohmann::json& c : row["candidates"]) {
    SCOPED_TRACE(c.dump());
    EXPECT_EQ(c["status"], "converged");
    EXPECT_GT(c["iterations"].get<int>(), 0);
    EXPECT_GT(c["intervals"].get<int>(), 0);
    EXPECT_TRUE(c["barrier"] == "warm" || c["barrier"] == "adaptive");
    EXPECT_GT(c["refine_ms"].get<double>(), 0.0);
    ++count;
  }
  const nlohmann::json& summary = result["summary"];
  EXPECT_EQ(summary["refine_ms"]["count"], count);
  EXPECT_EQ(summary["refine_ms_by_planner"]["prm_first"]["count"], count);
  EXPECT_GT(summary["iterations_by_planner"]["prm_first"]["median"].get<double>(), 0.0);
}

// Two shards merged hold exactly the cases of the whole suite; one shard alone is reported as
// incomplete; merging files of different suites is refused.
TEST_F(BenchCommandTest, ShardsMergeIntoTheWholeSuite) {
  const std::vector<std::string> common = {"bench", "tables", "--quick", "--seeds", "1"};
  auto with = [&common](std::vector<std::string> more) {
    std::vector<std::string> args = common;
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  ASSERT_EQ(run(with({"--out", path("all.json")})).status, 0);
  ASSERT_EQ(run(with({"--shard", "1/2", "--out", path("s1.json")})).status, 0);
  ASSERT_EQ(run(with({"--shard", "2/2", "--out", path("s2.json")})).status, 0);
  const nlohmann::json all = read(path("all.json"));
  const nlohmann::json s1 = read(path("s1.json")), s2 = read(path("s2.json"));
  EXPECT_EQ(s1["rows"].size() + s2["rows"].size(), all["rows"].size());
  const testing::CliRun merged =
      run({"bench", "merge", path("s2.json"), path("s1.json"), "--out", path("m.json")});
  ASSERT_EQ(merged.status, 0) << merged.err;
  const nlohmann::json m = read(path("m.json"));
  EXPECT_EQ(ids(m), ids(all));
  EXPECT_TRUE(m["missing_cases"].empty());
  // The merged wall time is the parts' (never the merge's own run time).
  EXPECT_NEAR(m["wall_time_s"].get<double>(),
              s1["wall_time_s"].get<double>() + s2["wall_time_s"].get<double>(), 1e-9);
  EXPECT_EQ(m["summary"]["by_tables"]["data"]["runs"], all["summary"]["by_tables"]["data"]["runs"]);
  for (std::size_t i = 0; i + 1 < m["rows"].size(); ++i) {
    EXPECT_LT(m["rows"][i]["case"].get<int>(), m["rows"][i + 1]["case"].get<int>());
  }
  const testing::CliRun partial = run({"bench", "merge", path("s1.json"), "--out", path("p.json")});
  EXPECT_EQ(partial.status, 0);
  EXPECT_EQ(read(path("p.json"))["missing_cases"].size(), s2["rows"].size());
  ASSERT_EQ(run({"bench", "convergence", "--quick", "--data-dir", "", "--cases", "0", "--out",
                 path("c.json")})
                .status,
            0);
  const testing::CliRun mixed = run({"bench", "merge", path("s1.json"), path("c.json")});
  EXPECT_EQ(mixed.status, kExitBadInput);
  EXPECT_NE(mixed.err.find("c.json"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("suite"), std::string::npos) << mixed.err;
}

// --jobs 2: the cases run in two worker processes of the real executable (Ipopt is not
// thread-safe); the result is the same list of cases.
TEST_F(BenchCommandTest, WorkersRunTheCasesInSeparateProcesses) {
  BenchOptions options;
  options.suite = "convergence";
  options.settings.quick = true;
  options.cases = "";
  // Cases 0, 29, 58, 87, 116: flat fan (newton_fd, newton), lattice (ipopt), hill (ceres), a
  // robustness turn (ceres).
  options.shard = "1/29";
  options.jobs = 2;
  // Workers run with the parent's settings (they check, and the parent compares their files).
  options.settings.interpolation = terrain::Interpolation::kBicubic;
  options.executable = TERRATRAJ_EXECUTABLE;
  options.out = path("w.json");
  std::ostringstream out, err;
  CommandContext context{out, err, false, nullptr};
  context.log = spdlog::default_logger();
  ASSERT_EQ(runBench(options, context), 0) << err.str();
  const nlohmann::json result = read(path("w.json"));
  ASSERT_EQ(result["rows"].size(), 5u) << err.str();
  EXPECT_EQ(result["rows"][0]["case"], 0);
  EXPECT_EQ(result["rows"][1]["case"], 29);
  EXPECT_EQ(result["rows"][2]["case"], 58);
  EXPECT_EQ(result["rows"][3]["case"], 87);
  EXPECT_EQ(result["rows"][4]["case"], 116);
  EXPECT_EQ(result["rows"][4]["family"], "robustness");
  EXPECT_EQ(result["processes"], 2);
  EXPECT_EQ(result["settings"]["interpolation"], "bicubic");
  for (const nlohmann::json& row : result["rows"]) {
    EXPECT_EQ(row["status"], "converged") << row.dump();
  }
}

TEST_F(BenchCommandTest, FiguresAreDrawn) {
  if (!fs::exists("/usr/bin/python3")) GTEST_SKIP() << "no /usr/bin/python3";
  const testing::CliRun r = run({"bench", "tables", "--quick", "--seeds", "1", "--out",
                                 path("t.json"), "--plot", path("t.png"), "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json brief = nlohmann::json::parse(r.out);
  ASSERT_EQ(brief["plots"]["status"], "ok") << brief["plots"].dump();
  EXPECT_GT(fs::file_size(path("t.png")), 10000u);
}

TEST_F(BenchCommandTest, BadInputIsNamedWithExitTwo) {
  const struct {
    std::vector<std::string> args;
    std::string named;
  } cases[] = {
      {{"bench", "speed"}, "speed"},
      {{"bench", "tables", "--shard", "3/2"}, "3/2"},
      {{"bench", "tables", "--shard", "half"}, "half"},
      {{"bench", "tables", "--seeds", "0"}, "--seeds"},
      {{"bench", "tables", "--time-limit", "nan"}, "time-limit"},
      {{"bench", "tables", "--jobs", "0"}, "--jobs"},
      {{"bench", "tables", "--cases", "7,x"}, "x"},
      {{"bench", "convergence", "--quick", "--data-dir", "/nonexistent", "--cases", "98"},
       "--data-dir: '/nonexistent'"},
      {{"bench", "merge", "/nonexistent.json"}, "/nonexistent.json"},
  };
  for (const auto& c : cases) {
    const testing::CliRun r = run(c.args);
    EXPECT_EQ(r.status, kExitBadInput) << c.args.back() << "\n" << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
  }
  std::ofstream(path("not.json")) << "{\"suite\": \"tables\"";
  const testing::CliRun r = run({"bench", "merge", path("not.json")});
  EXPECT_EQ(r.status, kExitBadInput);
  EXPECT_NE(r.err.find("not.json"), std::string::npos) << r.err;
}

// The surface is part of a result's settings; a file written before the key existed was measured
// on the bicubic surface, and says so when read back.
TEST(BenchSettings, TheSurfaceRoundTripsAndOldFilesReadAsBicubic) {
  BenchmarkSettings settings;
  EXPECT_EQ(settings.interpolation, terrain::Interpolation::kCubicBSpline);
  settings.interpolation = terrain::Interpolation::kBicubic;
  nlohmann::json json = settings.toJson();
  EXPECT_EQ(json["interpolation"], "bicubic");
  EXPECT_EQ(BenchmarkSettings::fromJson(json, "a.json").interpolation,
            terrain::Interpolation::kBicubic);
  json["interpolation"] = "bspline";
  EXPECT_EQ(BenchmarkSettings::fromJson(json, "a.json").interpolation,
            terrain::Interpolation::kCubicBSpline);
  json.erase("interpolation");
  EXPECT_EQ(BenchmarkSettings::fromJson(json, "old.json").interpolation,
            terrain::Interpolation::kBicubic);
  json["interpolation"] = "smooth";
  EXPECT_THROW(BenchmarkSettings::fromJson(json, "a.json"), terratraj::InputError);
}

// A figure that is not defined (no converged run) is "n/a", never 0.
TEST(BenchFigures, AnUndefinedFigureIsNotApplicable) {
  EXPECT_EQ(figureText(distributionJson({}), "median"), "n/a");
  EXPECT_EQ(figureText(nlohmann::json(nullptr), "median"), "n/a");
  EXPECT_EQ(figureText(distributionJson({2.0, 4.0}), "max"), "4");
}

// A stop request (SIGINT) before the first case: the result file is still written, with the
// rows finished (none) and `stopped_by`.
TEST_F(BenchCommandTest, AStoppedRunWritesWhatItHas) {
  BenchOptions options;
  options.suite = "tables";
  options.settings.quick = true;
  options.settings.seeds = 1;
  options.out = path("stopped.json");
  std::ostringstream out, err;
  const std::atomic<bool> stop{true};
  CommandContext context{out, err, false, nullptr};
  context.log = spdlog::default_logger();
  context.stop = &stop;
  runBench(options, context);
  const nlohmann::json result = read(path("stopped.json"));
  EXPECT_EQ(result["stopped_by"], "interrupt");
  EXPECT_TRUE(result["rows"].empty());
  EXPECT_GT(result["cases_total"].get<int>(), 0);
}

}  // namespace
}  // namespace terratraj::apps
