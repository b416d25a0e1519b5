#include "terratraj/apps/bench_command.hpp"

#include <spawn.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <thread>

#include "terratraj/apps/build_commit.hpp"
#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/output_paths.hpp"
#include "terratraj/apps/plot_writer.hpp"
#include "terratraj/terrain/input_error.hpp"

extern char** environ;

namespace terratraj::apps {

using bench::BenchmarkCase;
using bench::BenchmarkSuite;
using bench::makeBenchmarkSuite;
using bench::millisecondsSince;
namespace {

namespace fs = std::filesystem;

constexpr int kResultFormat = 1;

std::vector<int> parseCaseList(const std::string& text, int total) {
  std::vector<int> out;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      std::size_t used = 0;
      const int i = std::stoi(item, &used);
      if (used != item.size() || i < 0 || i >= total) throw std::invalid_argument(item);
      out.push_back(i);
    } catch (const std::exception&) {
      throw InputError("--cases: '" + item + "' is not a case index in [0, " +
                       std::to_string(total) + ")");
    }
  }
  return out;
}

fs::path defaultOut(const std::string& suite, const Shard& shard) {
  if (shard.count == 1) return "bench-" + suite + ".json";
  return "bench-" + suite + "-" + std::to_string(shard.index) + "-of-" +
         std::to_string(shard.count) + ".json";
}

nlohmann::json readResult(const fs::path& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path.string() + ": cannot be read");
  nlohmann::json json;
  try {
    file >> json;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not JSON (" + e.what() + ")");
  }
  for (const char* key : {"suite", "settings", "rows", "cases_total", "format"}) {
    if (!json.contains(key)) {
      throw InputError(path.string() + ": not a terratraj bench result (no '" + key + "')");
    }
  }
  if (json["format"] != kResultFormat) {
    throw InputError(path.string() + ": result format " + json["format"].dump() +
                     ", this build reads " + std::to_string(kResultFormat));
  }
  if (!json["rows"].is_array()) throw InputError(path.string() + ": 'rows' is not an array");
  for (const nlohmann::json& row : json["rows"]) {
    if (!row.contains("case") || !row["case"].is_number_integer()) {
      throw InputError(path.string() + ": a row without an integer 'case'");
    }
  }
  return json;
}

// Runs `cases` of `suite` in this process, one at a time, with a progress line per case.
nlohmann::json runHere(const BenchmarkSuite& suite, const std::vector<BenchmarkCase>& all,
                       const std::vector<int>& cases, const std::string& tag,
                       CommandContext& context) {
  nlohmann::json rows = nlohmann::json::array();
  int done = 0;
  for (const int i : cases) {
    if (context.stopRequested()) break;  // SIGINT: the finished rows are kept
    const auto started = std::chrono::steady_clock::now();
    nlohmann::json row = all[static_cast<std::size_t>(i)].run();
    row["case"] = i;
    row["id"] = all[static_cast<std::size_t>(i)].id;
    row["case_ms"] = millisecondsSince(started);
    ++done;
    context.err << "bench " << suite.name() << tag << " [" << done << "/" << cases.size() << "] "
                << row["id"].get<std::string>() << ": " << row.value("status", "done") << " ("
                << std::fixed << std::setprecision(0) << row["case_ms"].get<double>() << " ms)\n"
                << std::defaultfloat;
    rows.push_back(std::move(row));
  }
  return rows;
}

// Runs `cases` in `jobs` worker processes (`executable bench SUITE ... --cases ...`): Ipopt
// 3.11 with MUMPS is not thread-safe, processes are.
nlohmann::json runInWorkers(const BenchOptions& options, const std::vector<int>& cases,
                            CommandContext& context) {
  const fs::path folder =
      fs::temp_directory_path() /
      ("terratraj-bench-" + std::to_string(getpid()) + "-" +
       std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  fs::create_directories(folder);
  std::vector<pid_t> workers;
  std::vector<fs::path> outputs;
  const int jobs = std::min<int>(options.jobs, static_cast<int>(cases.size()));
  for (int j = 0; j < jobs; ++j) {
    std::string list;
    for (std::size_t k = static_cast<std::size_t>(j); k < cases.size();
         k += static_cast<std::size_t>(jobs)) {
      list += (list.empty() ? "" : ",") + std::to_string(cases[k]);
    }
    outputs.push_back(folder / ("worker-" + std::to_string(j) + ".json"));
    const BenchmarkSettings& s = options.settings;
    std::ostringstream seed, seeds, limit;
    seed << s.seed;
    seeds << s.seeds;
    limit << std::setprecision(17) << s.time_limit_s;
    std::vector<std::string> args = {
        options.executable.string(),
        "bench",
        options.suite,
        "--seed",
        seed.str(),
        "--seeds",
        seeds.str(),
        "--time-limit",
        limit.str(),
        "--data-dir",
        s.data_dir.string(),
        "--interpolation",
        terrain::interpolationName(s.interpolation),
        "--cases",
        list,
        "--worker-tag",
        " worker " + std::to_string(j + 1) + "/" + std::to_string(jobs),
        "--out",
        outputs.back().string()};
    if (s.quick) args.push_back("--quick");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) {
      throw InputError("cannot start a worker process (" + options.executable.string() + ")");
    }
    workers.push_back(pid);
  }
  std::string failures;
  for (std::size_t j = 0; j < workers.size(); ++j) {
    int status = 0;
    waitpid(workers[j], &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      failures += " worker " + std::to_string(j + 1) + " exited with " +
                  std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ";";
    }
  }
  nlohmann::json rows = nlohmann::json::array();
  if (failures.empty()) {
    const nlohmann::json settings = options.settings.toJson();
    for (const fs::path& output : outputs) {
      nlohmann::json part = readResult(output);
      if (part["settings"] != settings) {  // a worker must run what the parent was asked
        failures += " " + output.filename().string() + " ran with settings " +
                    part["settings"].dump() + ", not " + settings.dump() + ";";
      }
      for (nlohmann::json& row : part["rows"]) rows.push_back(std::move(row));
    }
  }
  fs::remove_all(folder);
  if (!failures.empty()) throw InputError("bench:" + failures);
  context.log->info("{} workers done", jobs);
  return rows;
}

void sortRows(nlohmann::json& rows) {
  std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a["case"].get<int>() < b["case"].get<int>();
  });
}

nlohmann::json resultJson(const BenchmarkSuite& suite, const BenchmarkSettings& settings,
                          int cases_total, nlohmann::json rows, const std::string& shard,
                          double wall_s) {
  sortRows(rows);
  nlohmann::json result;
  result["format"] = kResultFormat;
  result["suite"] = suite.name();
  result["machine"] = benchMachineJson();
  result["settings"] = settings.toJson();
  result["shard"] = shard;
  result["cases_total"] = cases_total;
  result["wall_time_s"] = wall_s;
  result["summary"] = suite.summarize(rows);
  result["rows"] = std::move(rows);
  return result;
}

nlohmann::json plotFigures(const fs::path& png, const fs::path& result_file,
                           CommandContext& context) {
  const BenchPlotOutcome outcome = writeBenchPlots(result_file, png, context);
  if (!outcome.error.empty()) {
    context.log->warn("no figures: {}", outcome.error);
    return {{"status", "error"}, {"error", outcome.error}};
  }
  nlohmann::json files = nlohmann::json::array();
  for (const fs::path& f : outcome.files) files.push_back(f.string());
  return {{"status", "ok"}, {"files", files}};
}

int finish(const BenchmarkSuite& suite, nlohmann::json result, const fs::path& out,
           const std::optional<fs::path>& plot, bool quiet, CommandContext& context) {
  writeJsonFile(result, out, 1);
  if (quiet) return kExitSuccess;  // a worker: its parent reads the file
  if (plot) {
    result["plots"] = plotFigures(*plot, out, context);
    writeJsonFile(result, out, 1);
  }
  if (context.json) {
    nlohmann::json brief = result;
    brief.erase("rows");
    brief["out"] = out.string();
    context.out << brief.dump(2) << '\n';
  } else {
    context.out << "bench " << suite.name() << ": " << result["rows"].size() << " of "
                << result["cases_total"] << " cases, " << result["wall_time_s"] << " s -> "
                << out.string() << '\n'
                << suite.summaryText(result["summary"]);
    if (result.contains("missing_cases") && !result["missing_cases"].empty()) {
      context.out << "missing cases: " << result["missing_cases"].size() << '\n';
    }
  }
  return kExitSuccess;
}

}  // namespace

Shard parseShard(const std::string& text) {
  Shard shard;
  const std::size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument(text);
    std::size_t used = 0;
    shard.index = std::stoi(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument(text);
    const std::string n = text.substr(slash + 1);
    shard.count = std::stoi(n, &used);
    if (used != n.size()) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    throw InputError("--shard: '" + text + "' is not K/N");
  }
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw InputError("--shard: '" + text + "' needs 1 <= K <= N");
  }
  return shard;
}

nlohmann::json benchMachineJson() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  utsname system{};
  uname(&system);
  const std::string commit = detail::kBuildCommit;
  std::string cpu;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  return {{"host", host},
          {"os", std::string(system.sysname) + " " + system.release},
          {"cpu", cpu},
          {"cores", std::thread::hardware_concurrency()},
          {"compiler", __VERSION__},
          {"commit", commit.empty() ? nlohmann::json(nullptr) : nlohmann::json(commit)},
          {"uncommitted_changes", detail::kBuildHadUncommittedChanges}};
}

int runBench(const BenchOptions& options, CommandContext& context) {
  const auto started = std::chrono::steady_clock::now();
  const std::unique_ptr<BenchmarkSuite> suite = makeBenchmarkSuite(options.suite, options.settings);
  const Shard shard = parseShard(options.shard);
  if (options.jobs < 1) throw InputError("--jobs must be >= 1");
  const std::vector<BenchmarkCase> all = suite->cases();
  const int total = static_cast<int>(all.size());
  std::vector<int> cases;
  if (!options.cases.empty()) {
    cases = parseCaseList(options.cases, total);
  } else {
    for (int i = shard.index - 1; i < total; i += shard.count) cases.push_back(i);
  }
  // Every output and input is checked before the first case: a long run must not lose its rows.
  const fs::path out = options.out.empty() ? defaultOut(suite->name(), shard) : options.out;
  ensureWritableFile(out, "--out");
  if (options.plot) ensureWritableFile(*options.plot, "--plot");
  if (!options.settings.data_dir.empty()) {
    ensureReadableFolder(options.settings.data_dir, "--data-dir");
  }
  for (const fs::path& input : suite->inputFiles()) {
    if (!std::ifstream(input)) {
      throw InputError("--data-dir: " + input.string() + " cannot be read (the " + suite->name() +
                       " suite needs it; --data-dir \"\" skips the real DEMs)");
    }
  }
  context.log->info("suite {}: {} of {} cases (shard {}), {} process(es)", suite->name(),
                    cases.size(), total, options.shard, options.jobs);
  const bool workers = options.jobs > 1 && cases.size() > 1;
  nlohmann::json rows = workers ? runInWorkers(options, cases, context)
                                : runHere(*suite, all, cases, options.worker_tag, context);
  nlohmann::json result = resultJson(*suite, options.settings, total, std::move(rows),
                                     options.shard, millisecondsSince(started) / 1000.0);
  result["processes"] = workers ? std::min<int>(options.jobs, static_cast<int>(cases.size())) : 1;
  if (context.stopRequested()) {
    result["stopped_by"] = "interrupt";
    context.log->warn("interrupted: {} of {} cases finished, written to {}", result["rows"].size(),
                      cases.size(), out.string());
  }
  return finish(*suite, std::move(result), out, options.plot, !options.worker_tag.empty(), context);
}

int runBenchMerge(const BenchMergeOptions& options, CommandContext& context) {
  if (options.inputs.empty()) throw InputError("bench merge: no input files");
  ensureWritableFile(options.out, "--out");
  if (options.plot) ensureWritableFile(*options.plot, "--plot");
  const auto started = std::chrono::steady_clock::now();
  nlohmann::json first;
  std::map<int, nlohmann::json> rows;
  double parts_wall_s = 0.0;
  nlohmann::json parts_wall = nlohmann::json::array();
  for (const fs::path& input : options.inputs) {
    nlohmann::json part = readResult(input);
    parts_wall_s += part.value("wall_time_s", 0.0);
    parts_wall.push_back(part.value("wall_time_s", 0.0));
    if (first.is_null()) {
      first = part;
    } else {
      for (const char* key : {"suite", "settings", "cases_total"}) {
        if (part[key] != first[key]) {
          throw InputError(input.string() + ": its " + key + " (" + part[key].dump() +
                           ") differs from " + options.inputs.front().string() + "'s (" +
                           first[key].dump() + ")");
        }
      }
    }
    for (nlohmann::json& row : part["rows"]) {
      const int i = row["case"].get<int>();
      auto [it, inserted] = rows.emplace(i, row);
      if (!inserted && it->second.value("id", "") != row.value("id", "")) {
        throw InputError(input.string() + ": case " + std::to_string(i) +
                         " is a different case than in an earlier file");
      }
    }
  }
  const std::string suite_name = first["suite"].get<std::string>();
  const BenchmarkSettings settings =
      BenchmarkSettings::fromJson(first["settings"], options.inputs.front().string());
  const std::unique_ptr<BenchmarkSuite> suite = makeBenchmarkSuite(suite_name, settings);
  nlohmann::json merged_rows = nlohmann::json::array();
  for (auto& [i, row] : rows) merged_rows.push_back(std::move(row));
  const int total = first["cases_total"].get<int>();
  // The merged run's wall time is not known (the parts may have run in parallel or in turn):
  // the sum of the parts' is reported, with each part's.
  nlohmann::json result =
      resultJson(*suite, settings, total, std::move(merged_rows), "merged", parts_wall_s);
  result["wall_time_s_of_parts"] = parts_wall;
  result["merge_time_s"] = millisecondsSince(started) / 1000.0;
  result["merged_from"] = nlohmann::json::array();
  for (const fs::path& input : options.inputs) result["merged_from"].push_back(input.string());
  nlohmann::json missing = nlohmann::json::array();
  for (int i = 0; i < total; ++i) {
    if (rows.count(i) == 0) missing.push_back(i);
  }
  result["missing_cases"] = missing;
  if (!missing.empty()) {
    context.log->warn("{} of {} cases are in none of the files", missing.size(), total);
  }
  return finish(*suite, std::move(result), options.out, options.plot, false, context);
}

}  // namespace terratraj::apps
