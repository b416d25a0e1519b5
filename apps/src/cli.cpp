#include "terratraj/apps/cli.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/sinks/ostream_sink.h>

#include <cstring>
#include <new>
#include <ostream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/terrain_commands.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

constexpr const char* kVersion = "terratraj 0.1.0";

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

std::string kindsHelp() {
  std::ostringstream text;
  text << "Kinds:\n";
  for (const std::string& name : terrain::terrainKindNames()) {
    text << "  " << name << std::string(12 - std::min<std::size_t>(name.size(), 11), ' ')
         << terrain::terrainKindDescription(*terrain::parseTerrainKind(name)) << '\n';
  }
  return text.str();
}

void addGeneratorOptions(CLI::App& command, terrain::GeneratorOptions& generator) {
  command.add_option("--rows", generator.rows, "cells along y (north)")->capture_default_str();
  command.add_option("--cols", generator.cols, "cells along x (east)")->capture_default_str();
  command.add_option("--cell", generator.cell, "cell size [m]")->capture_default_str();
  command.add_option("--seed", generator.seed, "random seed (same seed, same terrain)")
      ->capture_default_str();
}

}  // namespace

int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CommandContext context{out, err, wantsJson(argc, argv), makeLogger(err)};

  CLI::App app{"terratraj: optimal trajectories for ground rovers on terrain.", "terratraj"};
  app.set_version_flag("--version", kVersion);
  app.require_subcommand(1);
  bool json_flag = false;  // each command's --json sets this; wantsJson() already saw it

  DemoOptions demo;
  CLI::App* demo_command = app.add_subcommand(
      "demo", "The main job on built-in defaults, no input files: generates a terrain and writes "
              "it (GeoTIFF) and its summary (JSON) to the output folder.");
  demo_command->add_option("--out-dir", demo.out_dir, "output folder")->capture_default_str();
  addGeneratorOptions(*demo_command, demo.generator);
  demo_command->add_flag("--json", json_flag, "print the summary as one JSON object");

  CLI::App* terrain_command = app.add_subcommand("terrain", "Inspect or make terrain.");
  terrain_command->require_subcommand(1);

  TerrainInfoOptions info;
  CLI::App* info_command = terrain_command->add_subcommand(
      "info", "Size, cell, extent, height range, no-data count and slope statistics of a raster.");
  info_command->add_option("FILE", info.file, "any raster GDAL reads")->required();
  info_command->add_option("--cell", info.cell, "cell size [m] for rasters without georeferencing");
  info_command->add_option("--z-scale", info.z_scale, "multiplies heights")->capture_default_str();
  info_command->add_flag("--json", json_flag, "print one JSON object");

  TerrainGenerateOptions generate;
  std::string kind_name;
  CLI::App* generate_command =
      terrain_command->add_subcommand("generate", "Generate a synthetic terrain as GeoTIFF.");
  generate_command->add_option("KIND", kind_name, "terrain kind (listed below)")
      ->required()
      ->check(CLI::IsMember(terrain::terrainKindNames()));
  generate_command->add_option("--out", generate.out, "output GeoTIFF")->required();
  addGeneratorOptions(*generate_command, generate.generator);
  generate_command->add_flag("--json", json_flag, "print one JSON object");
  generate_command->footer(kindsHelp());

  CheckOptions check;
  CLI::App* check_command = app.add_subcommand(
      "check", "Read a problem file and its terrain, validate every key and the start and goal "
               "poses, and print what was understood.");
  check_command->add_option("PROBLEM", check.problem, "problem YAML")->required();
  check_command->add_flag("--json", json_flag, "print one JSON object");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e, out, err);  // --help, --version
    return reportError(e.what(), kExitBadInput, context);
  }

  try {
    if (*demo_command) return runDemo(demo, context);
    if (*info_command) return runTerrainInfo(info, context);
    if (*generate_command) {
      generate.generator.kind = *terrain::parseTerrainKind(kind_name);
      return runTerrainGenerate(generate, context);
    }
    if (*check_command) return runCheck(check, context);
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
