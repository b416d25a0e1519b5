#pragma once
// `terratraj lut build | check | physics | simulate-log`: kinodynamic look-up tables (003_...).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/models/driving_log_simulator.hpp"
#include "terratraj/models/kinodynamic_tables.hpp"

namespace terratraj::apps {

/// Bin edges as given on the command line: "e0,e1,...,en" (strictly increasing) or
/// "lo:hi:bins" (equal bins). Empty text gives `fallback`. Throws InputError naming `option`.
models::BinEdges parseBinEdges(const std::string& text, const models::BinEdges& fallback,
                               const std::string& option);

/// Options shared by the table-building commands.
struct TableBinning {
  std::string kind = "pitch";  ///< pitch | roll_curvature
  std::string pitch_edges;     ///< see parseBinEdges(); empty = defaults
  std::string roll_edges;
  std::string curvature_edges;
};

/// Options of `terratraj lut build`.
struct LutBuildOptions {
  std::filesystem::path log;
  std::filesystem::path out;
  TableBinning binning;
  models::DataTableOptions data;
};

/// Options of `terratraj lut check`.
struct LutCheckOptions {
  std::filesystem::path trajectory;
  std::vector<std::filesystem::path> tables;  ///< one pitch and/or one roll_curvature table
  double tolerance = 1e-9;                    ///< [m/s]
};

/// Options of `terratraj lut physics`.
struct LutPhysicsOptions {
  std::filesystem::path out;
  TableBinning binning;
  models::PhysicsTableParameters parameters;
};

/// Options of `terratraj lut simulate-log`.
struct LutSimulateOptions {
  std::filesystem::path out;
  models::DrivingLogOptions driver;
};

int runLutBuild(const LutBuildOptions& options, CommandContext& context);
int runLutCheck(const LutCheckOptions& options, CommandContext& context);
int runLutPhysics(const LutPhysicsOptions& options, CommandContext& context);
int runLutSimulateLog(const LutSimulateOptions& options, CommandContext& context);

}  // namespace terratraj::apps
