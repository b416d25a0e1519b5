#pragma once
// `terratraj demo`: the main job on built-in defaults, with no input files: a generated forest,
// TAEASL's routes (one per homotopy class), each refined into a locally optimal trajectory,
// the trajectories, the JSON report and the plots in the output folder, and a short summary.

#include <filesystem>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {

/// Options of `terratraj demo`.
struct DemoOptions {
  std::filesystem::path out_dir = "terratraj-demo";
  /// The built-in terrain: a 64 m x 64 m forest (many small lethal clusters).
  terrain::GeneratorOptions generator = [] {
    terrain::GeneratorOptions options;
    options.kind = terrain::TerrainKind::kForest;
    return options;
  }();
  bool plot = true;  ///< draw the PNG figures
};

/// The demo's problem on the terrain `generator` makes: the point vehicle from the standard
/// start to the standard goal (terrain::standardStartGoal) at rest, minimum time, TAEASL with
/// three classes for 1 s, each refined (auto method, 30 s per candidate at most).
ProblemSpec demoProblem(const terrain::GeneratorOptions& generator);

/// Runs the demo: writes terrain.tif, solution_<k>.csv, refined_<k>.csv, report.json (the
/// plan --refine report with the terrain's summary) and plot.png, plot-profiles.png,
/// plot-convergence.png to the output folder. Exit 0 when at least one route was refined, 1
/// otherwise; InputError (exit 2) for bad options or an unwritable folder.
int runDemo(const DemoOptions& options, CommandContext& context);

}  // namespace terratraj::apps
