#pragma once
// `terratraj terrain info`, `terratraj terrain generate` and `terratraj demo`.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"

namespace terratraj::apps {

/// Options of `terratraj terrain info`.
struct TerrainInfoOptions {
  std::filesystem::path file;
  std::optional<double> cell;  ///< --cell [m], for rasters without georeferencing
  double z_scale = 1.0;        ///< --z-scale
};

/// Options of `terratraj terrain generate`.
struct TerrainGenerateOptions {
  terrain::GeneratorOptions generator;
  std::filesystem::path out;
};

/// The JSON form of terrain statistics (lengths in metres, angles in radians).
nlohmann::json terrainStatisticsJson(const terrain::TerrainStatistics& stats);
/// A few lines a person reads, for the same statistics (angles in degrees).
std::string terrainStatisticsText(const terrain::TerrainStatistics& stats);

/// Prints the statistics of a raster. Throws InputError for a raster it cannot read.
int runTerrainInfo(const TerrainInfoOptions& options, CommandContext& context);
/// Generates a terrain and writes it as GeoTIFF. Throws InputError for bad options or paths.
int runTerrainGenerate(const TerrainGenerateOptions& options, CommandContext& context);

}  // namespace terratraj::apps
