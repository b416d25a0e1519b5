#include "terratraj/apps/cli.hpp"

#include <spdlog/sinks/ostream_sink.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <new>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/apps/bench_command.hpp"
#include "terratraj/apps/demo_command.hpp"
#include "terratraj/apps/lut_commands.hpp"
#include "terratraj/apps/plan_command.hpp"
#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/refine_command.hpp"
#include "terratraj/apps/solve_command.hpp"
#include "terratraj/apps/terrain_commands.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

constexpr const char* kVersion = kTerratrajVersion;

std::shared_ptr<spdlog::logger> makeLogger(std::ostream& err) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(err, /*force_flush=*/true);
  auto logger = std::make_shared<spdlog::logger>("terratraj", sink);
  logger->set_pattern("terratraj: %v");
  return logger;
}

// --json anywhere on the command line, so that errors found while parsing still honour it.
bool wantsJson(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0) return true;
  }
  return false;
}

int reportError(const std::string& message, int status, const CommandContext& context) {
  context.err << "terratraj: error: " << message << '\n';
  if (context.json) {
    context.out << nlohmann::json{{"status", "error"}, {"error", message}}.dump() << '\n';
  }
  return status;
}

// The real DEMs: $TERRATRAJ_DATA_DIR, else the repository's ../shared/data when it exists.
std::string defaultDataDir() {
  const char* configured = std::getenv("TERRATRAJ_DATA_DIR");
  if (configured != nullptr) return configured;
  const std::filesystem::path shared =
      std::filesystem::path(TERRATRAJ_SOURCE_DIR).parent_path() / "shared" / "data";
  std::error_code error;
  return std::filesystem::exists(shared, error) ? shared.string() : std::string();
}

std::string kindsHelp() {
  std::ostringstream text;
  text << "Kinds:\n";
  for (const std::string& name : terrain::terrainKindNames()) {
    text << "  " << name << std::string(12 - std::min<std::size_t>(name.size(), 11), ' ')
         << terrain::terrainKindDescription(*terrain::parseTerrainKind(name)) << '\n';
  }
  return text.str();
}

// Numbers on the command line are read as the problem file reads them: decimal only. CLI11
// alone would take "0x1" for 1 and wrap "-1" into 2^64 - 1 for an unsigned seed.
// Grammar: [+-] (digits [. digits*] | . digits) [(e|E) [+-] digits].
bool isDecimalNumber(const std::string& text) {
  std::size_t at = 0;
  const auto digitsFrom = [&text](std::size_t from) {
    std::size_t end = from;
    while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end])) != 0) ++end;
    return end - from;
  };
  if (at < text.size() && (text[at] == '+' || text[at] == '-')) ++at;
  const std::size_t whole = digitsFrom(at);
  at += whole;
  std::size_t fraction = 0;
  if (at < text.size() && text[at] == '.') {
    fraction = digitsFrom(at + 1);
    at += 1 + fraction;
  }
  if (whole == 0 && fraction == 0) return false;
  if (at < text.size() && (text[at] == 'e' || text[at] == 'E')) {
    ++at;
    if (at < text.size() && (text[at] == '+' || text[at] == '-')) ++at;
    const std::size_t exponent = digitsFrom(at);
    if (exponent == 0) return false;
    at += exponent;
  }
  return at == text.size();
}

bool isWholeNumber(const std::string& text) {
  const std::size_t first = (!text.empty() && text[0] == '+') ? 1 : 0;
  if (first == text.size()) return false;
  return std::all_of(text.begin() + static_cast<std::ptrdiff_t>(first), text.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

const CLI::Validator kDecimal(
    [](std::string& text) -> std::string {
      return isDecimalNumber(text) ? std::string() : "'" + text + "' is not a decimal number";
    },
    "DECIMAL");
const CLI::Validator kCount(
    [](std::string& text) -> std::string {
      return isWholeNumber(text) ? std::string()
                                 : "'" + text + "' is not a whole number >= 0 (decimal digits)";
    },
    "INTEGER >= 0");

// The first argument, when it is neither an option nor a command: a typo to name.
std::optional<std::string> unknownCommand(int argc, const char* const* argv, const CLI::App& app) {
  if (argc < 2 || argv[1][0] == '-') return std::nullopt;
  const std::string first = argv[1];
  std::string names;
  for (const CLI::App* command : app.get_subcommands({})) {
    if (command->get_name() == first) return std::nullopt;
    names += (names.empty() ? "" : ", ") + command->get_name();
  }
  return "unknown command '" + first + "' (commands: " + names + "; see --help)";
}

void addBinningOptions(CLI::App& command, TableBinning& binning) {
  command.add_option("--kind", binning.kind, "pitch | roll_curvature")
      ->capture_default_str()
      ->check(CLI::IsMember({"pitch", "roll_curvature"}));
  command.add_option("--pitch-edges", binning.pitch_edges,
                     "pitch bin edges [rad]: e0,e1,...,en or lo:hi:bins (default -0.4:0.4:16)");
  command.add_option("--roll-edges", binning.roll_edges,
                     "roll bin edges [rad] (default -0.4:0.4:16)");
  command.add_option("--curvature-edges", binning.curvature_edges,
                     "curvature bin edges [1/m] (default -1:1:20)");
}

void addGeneratorOptions(CLI::App& command, terrain::GeneratorOptions& generator) {
  command.add_option("--rows", generator.rows, "cells along y (north)")
      ->capture_default_str()
      ->check(kCount);
  command.add_option("--cols", generator.cols, "cells along x (east)")
      ->capture_default_str()
      ->check(kCount);
  command.add_option("--cell", generator.cell, "cell size [m]")
      ->capture_default_str()
      ->check(kDecimal);
  command.add_option("--seed", generator.seed, "random seed (same seed, same terrain)")
      ->capture_default_str()
      ->check(kCount);
}

// One command of the tool: its parsed options live in `run`'s closure; `run` is called when
// the command was given.
struct Command {
  CLI::App* app = nullptr;
  std::function<int(CommandContext&)> run;
};

// Each add*() declares one command (its options and help) under `parent`; every --json sets
// `json_flag` (wantsJson() has already seen it).

Command addDemo(CLI::App& parent, bool& json_flag) {
  auto demo = std::make_shared<DemoOptions>();
  CLI::App* command = parent.add_subcommand(
      "demo",
      "The main job on built-in defaults, no input files: generates a forest, plans with TAEASL "
      "(one route per homotopy class), refines every route, and writes the terrain, the "
      "trajectories, report.json and the plots to the output folder.");
  command->add_option("--out-dir", demo->out_dir, "output folder")->capture_default_str();
  addGeneratorOptions(*command, demo->generator);
  command->add_flag("!--no-plot", demo->plot, "skip the PNG figures");
  command->add_flag("--json", json_flag, "print the report as one JSON object");
  return {command, [demo](CommandContext& context) { return runDemo(*demo, context); }};
}

std::vector<Command> addTerrain(CLI::App& parent, bool& json_flag) {
  CLI::App* terrain_command = parent.add_subcommand("terrain", "Inspect or make terrain.");
  terrain_command->require_subcommand(1);

  auto info = std::make_shared<TerrainInfoOptions>();
  CLI::App* info_command = terrain_command->add_subcommand(
      "info", "Size, cell, extent, height range, no-data count and slope statistics of a raster.");
  info_command->add_option("FILE", info->file, "any raster GDAL reads")->required();
  info_command->add_option("--cell", info->cell,
                           "cell size [m] for rasters without georeferencing");
  info_command->add_option("--z-scale", info->z_scale, "multiplies heights")->capture_default_str();
  info_command->add_flag("--json", json_flag, "print one JSON object");

  struct Generate {
    TerrainGenerateOptions options;
    std::string kind_name;
  };
  auto generate = std::make_shared<Generate>();
  CLI::App* generate_command =
      terrain_command->add_subcommand("generate", "Generate a synthetic terrain as GeoTIFF.");
  generate_command->add_option("KIND", generate->kind_name, "terrain kind (listed below)")
      ->required()
      ->check(CLI::IsMember(terrain::terrainKindNames()));
  generate_command->add_option("--out", generate->options.out, "output GeoTIFF")->required();
  addGeneratorOptions(*generate_command, generate->options.generator);
  generate_command->add_flag("--json", json_flag, "print one JSON object");
  generate_command->footer(kindsHelp());
  return {
      {info_command, [info](CommandContext& context) { return runTerrainInfo(*info, context); }},
      {generate_command, [generate](CommandContext& context) {
         generate->options.generator.kind = *terrain::parseTerrainKind(generate->kind_name);
         return runTerrainGenerate(generate->options, context);
       }}};
}

Command addCheck(CLI::App& parent, bool& json_flag) {
  auto check = std::make_shared<CheckOptions>();
  CLI::App* command = parent.add_subcommand(
      "check",
      "Read a problem file and its terrain, validate every key and the start and goal "
      "poses, and print what was understood.");
  command->add_option("PROBLEM", check->problem, "problem YAML")->required();
  command->add_flag("--json", json_flag, "print one JSON object");
  return {command, [check](CommandContext& context) { return runCheck(*check, context); }};
}

Command addSolve(CLI::App& parent, bool& json_flag) {
  auto solve = std::make_shared<SolveOptions>();
  CLI::App* command = parent.add_subcommand(
      "solve",
      "One boundary-value problem: from the problem's start to its goal, a trajectory locally "
      "optimal for its cost (auto, newton, newton_fd, ipopt, ceres, shooting, collocation). "
      "Exit 0 converged, 1 not solved (the report says why), 2 bad input.");
  command->add_option("PROBLEM", solve->problem, "problem YAML")->required();
  command->add_option("--method", solve->method, "overrides solver.method")
      ->check(CLI::IsMember(solverMethodNames()));
  command->add_option("--out", solve->out, "write the re-simulated trajectory (CSV)");
  command->add_option("--guess", solve->guess,
                      "shooting / collocation: initial guess from a trajectory or x,y CSV");
  command->add_option("--plot", solve->plot,
                      "draw the map, profiles and convergence (PNG; FILE, FILE-profiles, "
                      "FILE-convergence)");
  command->add_flag("--json", json_flag, "print the report as one JSON object");
  return {command, [solve](CommandContext& context) { return runSolve(*solve, context); }};
}

Command addPlan(CLI::App& parent, bool& json_flag) {
  auto plan = std::make_shared<PlanOptions>();
  CLI::App* command = parent.add_subcommand(
      "plan",
      "Global planning from the problem's start to its goal region: the kinodynamic PRM "
      "(prm, anytime), the state lattice with A* / ARA* (lattice) or the topology-aware lattice "
      "(taeasl: one solution per homotopy class). Writes <out-dir>/solution_<k>.csv; with "
      "--refine, also <out-dir>/refined_<k>.csv, each candidate refined into a locally optimal "
      "trajectory in its homotopy class. Exit 0 solved (and with --refine at least one "
      "refinement converged), 1 not, 2 bad input.");
  command->add_option("PROBLEM", plan->problem, "problem YAML")->required();
  command->add_option("--planner", plan->planner, "overrides planner.kind (prm, lattice, taeasl)")
      ->check(CLI::IsMember(plannerKindNames()));
  command->add_option("--time-limit", plan->time_limit_s, "overrides planner.time_limit_s [s]")
      ->check(kDecimal);
  command->add_option("--seed", plan->seed, "overrides planner.seed")->check(kCount);
  command->add_option("--out-dir", plan->out_dir, "output folder")->capture_default_str();
  command->add_flag("--refine", plan->refine,
                    "refine every solution (refine.method; docs/refinement.md)");
  command->add_option("--method", plan->method, "with --refine: overrides refine.method")
      ->check(CLI::IsMember(refine::refineMethodNames()));
  command->add_option("--plot", plan->plot,
                      "draw the map, profiles and convergence (PNG; FILE, FILE-profiles, "
                      "FILE-convergence)");
  command->add_flag("--json", json_flag, "print the report as one JSON object");
  return {command, [plan](CommandContext& context) { return runPlan(*plan, context); }};
}

Command addRefine(CLI::App& parent, bool& json_flag) {
  auto refine = std::make_shared<RefineOptions>();
  CLI::App* command = parent.add_subcommand(
      "refine",
      "Refine a given path or trajectory (a planner's or another tool's CSV: the contract's "
      "columns, or only x,y, or x,y,heading) into a locally optimal trajectory from the "
      "problem's start to its goal, in the candidate's homotopy class. Exit 0 converged, 1 "
      "not (the report says why), 2 bad input (including an unusable candidate).");
  command->add_option("PROBLEM", refine->problem, "problem YAML")->required();
  command->add_option("--candidate", refine->candidate, "the candidate CSV")->required();
  command->add_option("--method", refine->method, "overrides refine.method")
      ->check(CLI::IsMember(refine::refineMethodNames()));
  command->add_option("--out", refine->out, "write the refined trajectory (CSV)");
  command->add_option("--plot", refine->plot,
                      "draw the map, profiles and convergence (PNG; FILE, FILE-profiles, "
                      "FILE-convergence)");
  command->add_flag("--json", json_flag, "print the report as one JSON object");
  return {command, [refine](CommandContext& context) { return runRefine(*refine, context); }};
}

// bench and bench merge (merge first: a subcommand of bench, both are "given" with it).
std::vector<Command> addBench(CLI::App& parent, bool& json_flag) {
  auto bench = std::make_shared<BenchOptions>();
  bench->settings.data_dir = defaultDataDir();
  CLI::App* command = parent.add_subcommand(
      "bench",
      "Benchmark suites (docs/benchmarks.md): convergence (every boundary-value solver on the "
      "004 problem sets and random problems on the real DEMs, and the robustness set), "
      "robustness (the core's robustness set alone: turns, turn-backs, every vehicle on the "
      "DEMs), planners (001's size and "
      "expansiveness sweeps, the lattice searches), refine (candidates against their "
      "refinements), tables (003 IV: physics-derived against data-driven tables). Writes one "
      "JSON file per run; `bench merge` joins shards.");
  command->add_option("SUITE", bench->suite,
                      "convergence | robustness | planners | refine | tables");
  command->add_flag("--quick", bench->settings.quick,
                    "a small subset of every set (seconds instead of minutes)");
  command->add_option("--seed", bench->settings.seed, "first seed of every random choice")
      ->capture_default_str()
      ->check(kCount);
  command->add_option("--seeds", bench->settings.seeds, "repetitions (maps, planner seeds)")
      ->capture_default_str()
      ->check(kCount);
  command
      ->add_option("--time-limit", bench->settings.time_limit_s,
                   "planners: longest anytime budget [s]")
      ->capture_default_str()
      ->check(kDecimal);
  command
      ->add_option("--data-dir", bench->settings.data_dir,
                   "folder of the real DEMs (\"\" skips them)")
      ->capture_default_str();
  command
      ->add_option("--interpolation", bench->settings.interpolation,
                   "the surface of the convergence and robustness sets' maps: bspline (C2, the "
                   "default of every command) or bicubic (C1)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, terrain::Interpolation>{
              {"bspline", terrain::Interpolation::kCubicBSpline},
              {"bicubic", terrain::Interpolation::kBicubic}},
          CLI::ignore_case))
      ->default_str("bspline");
  command->add_option("--out", bench->out, "result file (default bench-SUITE.json)");
  command->add_option("--plot", bench->plot, "also draw the figures: FILE.png and siblings");
  command->add_option("--shard", bench->shard, "K/N: run every N-th case from the K-th")
      ->capture_default_str();
  command->add_option("--jobs", bench->jobs, "worker processes")
      ->capture_default_str()
      ->check(kCount);
  command->add_option("--cases", bench->cases, "case indices (used by workers)")->group("");
  command->add_option("--worker-tag", bench->worker_tag, "(used by workers)")->group("");
  command->add_flag("--json", json_flag, "print the result (without rows) as JSON");

  auto merge = std::make_shared<BenchMergeOptions>();
  CLI::App* merge_command =
      command->add_subcommand("merge", "Join result files of shards into one.");
  merge_command->add_option("FILES", merge->inputs, "result files")->required();
  merge_command->add_option("--out", merge->out, "merged file")->capture_default_str();
  merge_command->add_option("--plot", merge->plot, "also draw the figures");
  merge_command->add_flag("--json", json_flag, "print the result (without rows) as JSON");
  return {
      {merge_command, [merge](CommandContext& context) { return runBenchMerge(*merge, context); }},
      {command, [bench](CommandContext& context) {
         if (bench->suite.empty()) {
           throw InputError(
               "bench: name a suite (convergence, robustness, planners, refine, tables) or "
               "merge");
         }
         return runBench(*bench, context);
       }}};
}

Command addPrimitives(CLI::App& parent, bool& json_flag) {
  auto primitives = std::make_shared<PrimitivesOptions>();
  CLI::App* command = parent.add_subcommand(
      "primitives",
      "Generate the motion primitives of the problem's lattice (planner.lattice_resolution_m, "
      "planner.heading_count) for its vehicle limits, with the boundary-value solver on flat "
      "ground, and write them as JSON (for planner.primitives).");
  command->add_option("PROBLEM", primitives->problem, "problem YAML")->required();
  command->add_option("--out", primitives->out, "primitive file to write")->required();
  command->add_flag("--json", json_flag, "print the report as one JSON object");
  return {command,
          [primitives](CommandContext& context) { return runPrimitives(*primitives, context); }};
}

Command addLutBuild(CLI::App& lut, bool& json_flag) {
  auto build = std::make_shared<LutBuildOptions>();
  CLI::App* command = lut.add_subcommand(
      "build",
      "Data-driven table from a driving log: each bin holds the mean of the top 1 % of "
      "its speeds; bins without data hold 0.");
  command
      ->add_option("--log", build->log,
                   "driving log (trajectory CSV with roll, "
                   "pitch, v and curvature or omega)")
      ->required();
  command->add_option("--out", build->out, "table JSON to write")->required();
  addBinningOptions(*command, build->binning);
  command
      ->add_option("--top-fraction", build->data.top_fraction,
                   "fraction of each bin's fastest speeds averaged")
      ->capture_default_str();
  command->add_flag("--fill", build->data.fill_empty,
                    "fill empty bins between filled ones by linear interpolation");
  command->add_flag("--json", json_flag, "print one JSON object");
  return {command, [build](CommandContext& context) { return runLutBuild(*build, context); }};
}

Command addLutCheck(CLI::App& lut, bool& json_flag) {
  auto check = std::make_shared<LutCheckOptions>();
  CLI::App* command = lut.add_subcommand(
      "check", "Fraction of a trajectory's states faster than the tables allow.");
  command->add_option("TRAJECTORY", check->trajectory, "trajectory CSV")->required();
  command
      ->add_option("--table", check->tables,
                   "table JSON (repeat for a pitch and a roll_curvature table)")
      ->required();
  command->add_option("--tolerance", check->tolerance, "speed above v_max tolerated [m/s]")
      ->capture_default_str();
  command->add_flag("--json", json_flag, "print one JSON object");
  return {command, [check](CommandContext& context) { return runLutCheck(*check, context); }};
}

Command addLutPhysics(CLI::App& lut, bool& json_flag) {
  auto physics = std::make_shared<LutPhysicsOptions>();
  CLI::App* command = lut.add_subcommand(
      "physics",
      "Physics-derived table (003_... appendix I: tip-over in turns, braking distance).");
  command->add_option("--out", physics->out, "table JSON to write")->required();
  addBinningOptions(*command, physics->binning);
  models::PhysicsTableParameters& p = physics->parameters;
  command->add_option("--half-track", p.half_track, "[m]")->capture_default_str();
  command->add_option("--cog-height", p.cog_height, "[m]")->capture_default_str();
  command->add_option("--friction", p.friction, "friction coefficient")->capture_default_str();
  command->add_option("--vehicle-length", p.vehicle_length, "[m] (braking distance = 2 lengths)")
      ->capture_default_str();
  command->add_option("--speed-cap", p.speed_cap, "[m/s]")->capture_default_str();
  command->add_flag("--json", json_flag, "print one JSON object");
  return {command, [physics](CommandContext& context) { return runLutPhysics(*physics, context); }};
}

Command addLutSimulateLog(CLI::App& lut, bool& json_flag) {
  auto simulate = std::make_shared<LutSimulateOptions>();
  CLI::App* command =
      lut.add_subcommand("simulate-log",
                         "Simulated expert driving log (a driver who drives fast but avoids hard "
                         "turns with the roll against them) on generated hills.");
  command->add_option("--out", simulate->out, "trajectory CSV to write")->required();
  command->add_option("--seed", simulate->driver.seed)->capture_default_str()->check(kCount);
  command->add_option("--duration", simulate->driver.duration, "[s]")->capture_default_str();
  command->add_flag("--json", json_flag, "print one JSON object");
  return {command,
          [simulate](CommandContext& context) { return runLutSimulateLog(*simulate, context); }};
}

std::vector<Command> addLut(CLI::App& parent, bool& json_flag) {
  CLI::App* lut = parent.add_subcommand(
      "lut", "Kinodynamic look-up tables (speed limits by pitch, roll x curvature).");
  lut->require_subcommand(1);
  return {addLutBuild(*lut, json_flag), addLutCheck(*lut, json_flag),
          addLutPhysics(*lut, json_flag), addLutSimulateLog(*lut, json_flag)};
}

// Every command, in the order of --help; a command before its parent.
std::vector<Command> addCommands(CLI::App& app, bool& json_flag) {
  std::vector<Command> commands{addDemo(app, json_flag)};
  const auto append = [&commands](std::vector<Command> more) {
    for (Command& command : more) commands.push_back(std::move(command));
  };
  append(addTerrain(app, json_flag));
  commands.push_back(addCheck(app, json_flag));
  commands.push_back(addSolve(app, json_flag));
  commands.push_back(addPlan(app, json_flag));
  commands.push_back(addRefine(app, json_flag));
  append(addBench(app, json_flag));
  commands.push_back(addPrimitives(app, json_flag));
  append(addLut(app, json_flag));
  return commands;
}

}  // namespace

int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
           const std::atomic<bool>* stop) {
  CommandContext context{out, err, wantsJson(argc, argv), makeLogger(err), stop};
  CLI::App app{"terratraj: optimal trajectories for ground rovers on terrain.", "terratraj"};
  app.set_version_flag("--version", kVersion);
  app.require_subcommand(1);
  bool json_flag = false;  // each command's --json sets this; wantsJson() already saw it
  const std::vector<Command> commands = addCommands(app, json_flag);

  if (const std::optional<std::string> unknown = unknownCommand(argc, argv, app)) {
    return reportError(*unknown, kExitBadInput, context);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e, out, err);  // --help, --version
    return reportError(e.what(), kExitBadInput, context);
  }
  try {
    for (const Command& command : commands) {
      if (*command.app) return command.run(context);
    }
  } catch (const InputError& e) {
    return reportError(e.what(), kExitBadInput, context);
  } catch (const std::bad_alloc&) {
    return reportError("out of memory (is the input too large?)", kExitBadInput, context);
  } catch (const std::exception& e) {
    return reportError(std::string("internal error: ") + e.what(), kExitInternal, context);
  }
  return reportError("no command given (see --help)", kExitBadInput, context);
}

}  // namespace terratraj::apps
