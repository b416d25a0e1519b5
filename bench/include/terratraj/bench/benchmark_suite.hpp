#pragma once
// BenchmarkSuite: one suite of `terratraj bench` (convergence, planners, refine, tables): a
// deterministic list of cases (one JSON row each, so that shards and worker processes can split
// them) and a summary of the rows. Suites compute; BenchCommand runs, shards, merges, writes.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {

/// What every suite reads. Defaults are the full suites of docs/benchmarks.md.
struct BenchmarkSettings {
  bool quick = false;        ///< a small subset of every set (minutes become seconds), for tests
  std::uint64_t seed = 1;    ///< first seed of every random choice (maps, problems, planners)
  int seeds = 3;             ///< repetitions with seeds seed .. seed + seeds - 1, >= 1
  double time_limit_s = 10;  ///< planners: longest anytime budget [s] (costs at 1 s and this)
  std::filesystem::path data_dir;  ///< the real DEMs (convergence); empty: no DEM problems
  /// The surface of the convergence and robustness sets' maps (`--interpolation`). A result file
  /// without the key was written before it existed, on the bicubic surface.
  terrain::Interpolation interpolation = terrain::kDefaultInterpolation;
  /// Settings as written to and read from a result file. fromJson throws InputError naming the
  /// key at fault.
  nlohmann::json toJson() const;
  static BenchmarkSettings fromJson(const nlohmann::json& json, const std::string& source);
};

/// One unit of work: run() returns its row (never throws for a failed solve: the failure is in
/// the row; throws InputError only for bad input such as a missing DEM).
struct BenchmarkCase {
  std::string id;  ///< unique within the suite, e.g. "rough_lattice/17/ipopt"
  std::function<nlohmann::json()> run;
};

class BenchmarkSuite {
 public:
  virtual ~BenchmarkSuite() = default;
  virtual std::string name() const = 0;
  /// The cases in a fixed order (the same for the same settings on every machine).
  virtual std::vector<BenchmarkCase> cases() const = 0;
  /// Summary of `rows` (any subset of the cases' rows, e.g. after a merge).
  virtual nlohmann::json summarize(const nlohmann::json& rows) const = 0;
  /// A few lines a person reads on stdout.
  virtual std::string summaryText(const nlohmann::json& summary) const = 0;
  /// The files the cases will read (checked before any case runs).
  virtual std::vector<std::filesystem::path> inputFiles() const { return {}; }
};

/// "convergence", "planners", "refine", "tables".
std::vector<std::string> benchmarkSuiteNames();
/// The suite called `name`; throws InputError for an unknown name.
std::unique_ptr<BenchmarkSuite> makeBenchmarkSuite(const std::string& name,
                                                   const BenchmarkSettings& settings);

std::unique_ptr<BenchmarkSuite> makeConvergenceSuite(const BenchmarkSettings& settings);
std::unique_ptr<BenchmarkSuite> makePlannersSuite(const BenchmarkSettings& settings);
std::unique_ptr<BenchmarkSuite> makeRefineSuite(const BenchmarkSettings& settings);
std::unique_ptr<BenchmarkSuite> makeTablesSuite(const BenchmarkSettings& settings);
std::unique_ptr<BenchmarkSuite> makeRobustnessSuite(const BenchmarkSettings& settings);

/// The robustness set's cases (rows with "family": "robustness"), its summary and text, and the
/// DEMs it reads: `bench robustness` alone, and part of `bench convergence`.
std::vector<BenchmarkCase> robustnessCases(const BenchmarkSettings& settings);
nlohmann::json summarizeRobustness(const nlohmann::json& rows);
std::string robustnessText(const nlohmann::json& summary);
std::vector<std::filesystem::path> robustnessInputs(const BenchmarkSettings& settings);

/// {"count", "median", "p90", "min", "max", "mean"} of `values` ({"count": 0} when empty).
nlohmann::json distributionJson(std::vector<double> values);
/// `distribution[key]` for a summary line, or "n/a" when it is absent or null (an empty
/// distribution, an undefined ratio): never a 0 that was not measured.
std::string figureText(const nlohmann::json& distribution, const char* key);
/// Wall time since `start` [ms].
double millisecondsSince(std::chrono::steady_clock::time_point start);

}  // namespace terratraj::bench
