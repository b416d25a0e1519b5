#pragma once
// `terratraj bench SUITE` and `terratraj bench merge`: runs a BenchmarkSuite's cases (a shard of
// them, in worker processes when --jobs > 1), writes one JSON result file (machine, commit,
// settings, every row, the summary), optionally the figures; merges shards' files.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/bench/benchmark_suite.hpp"

namespace terratraj::apps {

using bench::BenchmarkSettings;

/// A shard K/N: this run takes the cases whose index i satisfies i % N == K - 1.
struct Shard {
  int index = 1;  ///< K, 1-based
  int count = 1;  ///< N
};
/// Parses "K/N" (1 <= K <= N); throws InputError naming the text.
Shard parseShard(const std::string& text);

/// Options of `terratraj bench SUITE`.
struct BenchOptions {
  std::string suite;
  BenchmarkSettings settings;
  std::filesystem::path out;                  ///< result file; empty: bench-<suite>[-K-of-N].json
  std::optional<std::filesystem::path> plot;  ///< PNG figure(s) of the summary
  std::string shard = "1/1";
  int jobs = 1;            ///< worker processes (each runs its cases one at a time)
  std::string cases;       ///< internal (workers): comma-separated case indices to run
  std::string worker_tag;  ///< internal (workers): text added to the progress lines
  std::filesystem::path executable = "/proc/self/exe";  ///< what workers run
};

/// Options of `terratraj bench merge`.
struct BenchMergeOptions {
  std::vector<std::filesystem::path> inputs;
  std::filesystem::path out = "bench-merged.json";
  std::optional<std::filesystem::path> plot;
};

/// Where the machine and the code are: host, cores, OS, compiler, and the commit the binary
/// was built from (and whether the tree had uncommitted changes then).
nlohmann::json benchMachineJson();

int runBench(const BenchOptions& options, CommandContext& context);
int runBenchMerge(const BenchMergeOptions& options, CommandContext& context);

}  // namespace terratraj::apps
