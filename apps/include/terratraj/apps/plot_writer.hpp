#pragma once
// PlotWriter: the PNG figures of `--plot` (map, profiles, convergence), drawn by matplotlib:
// the request (map raster, trajectories, histories, frames, limits) is written as files and
// scripts/plot_results.py (embedded in the executable) is run by Debian's /usr/bin/python3
// (or $TERRATRAJ_PYTHON).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::apps {

/// One trajectory to draw.
struct PlotTrajectory {
  std::string label;          ///< legend text
  std::filesystem::path csv;  ///< the contract's trajectory CSV
  bool candidate = false;     ///< candidates are drawn thin and dashed; others coloured by speed
  int group = 0;              ///< candidates and their refinements share a colour
};

/// One solver's iteration history (convergence figure).
struct PlotHistory {
  std::string label;
  std::vector<ocp::IterationRecord> iterations;
  int group = 0;
};

/// A start or goal pose [m, rad, local frame].
struct PlotPose {
  double x = 0.0, y = 0.0, heading = 0.0;
};

/// A reference frame of TAEASL [m, local frame].
struct PlotFrame {
  std::string name;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
};

/// The reference frames as drawn, named by HomotopySignature::frameName.
std::vector<PlotFrame> plotFrames(const search::ReferenceFrames& frames);

/// Everything the three figures show.
struct PlotRequest {
  std::string title;
  std::vector<PlotTrajectory> trajectories;
  std::vector<PlotHistory> histories;
  std::vector<PlotFrame> frames;
  std::optional<PlotPose> start, goal;
  models::VehicleLimits limits;
  double tolerance_position_m = 0.0;  ///< drawn on the convergence figure when > 0
};

/// The three PNG files of `--plot FILE.png`: FILE.png (map), FILE-profiles.png and
/// FILE-convergence.png beside it.
struct PlotFiles {
  std::filesystem::path map, profiles, convergence;
};
/// The file names for `--plot png`.
PlotFiles plotFiles(const std::filesystem::path& png);

/// Draws the figures of `request` on `map`. Writes the request next to the map figure in
/// FILE-plot/ (the raster, its mask, request.json and the script) and runs the script. Returns
/// the files on success; throws InputError when the folder cannot be written, and returns an
/// error message (std::nullopt files) when the plotting process fails (no python3 or
/// matplotlib: the message says which package to install).
struct PlotOutcome {
  std::optional<PlotFiles> files;
  std::string error;  ///< why there are no files
  /// {"map", "profiles", "convergence"} or {"error"}.
  nlohmann::json toJson() const;
};
PlotOutcome writePlots(const PlotRequest& request, const terrain::ElevationMap& map,
                       const std::filesystem::path& png, CommandContext& context);

/// The figures of a `terratraj bench` result file (scripts/plot_bench.py, embedded): `png` and
/// siblings named after it (which depend on the suite). Returns the files written, or why none
/// were (as writePlots). Throws InputError when the folder cannot be written.
struct BenchPlotOutcome {
  std::vector<std::filesystem::path> files;
  std::string error;  ///< empty on success
};
BenchPlotOutcome writeBenchPlots(const std::filesystem::path& result_file,
                                 const std::filesystem::path& png, CommandContext& context);

}  // namespace terratraj::apps
