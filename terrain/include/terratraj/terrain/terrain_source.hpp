#pragma once
// TerrainSource: where a problem's terrain comes from (the `terrain:` section of the problem
// YAML, ../shared/spec/interface.md), and loadTerrain(), which builds the map it describes.

#include <filesystem>
#include <optional>

#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::terrain {

/// Which coordinates a problem's poses are written in.
enum class CoordinateFrame {
  kLocal,  ///< origin at the lower-left corner of the lower-left cell (default)
  kWorld,  ///< the raster's georeferenced coordinates
};

/// Where the lethal layer comes from; both may be given, and their union is lethal.
struct ObstacleSource {
  std::optional<std::filesystem::path> file;  ///< raster, non-zero = lethal
  /// Band of `file` (from 1), or of the terrain's own raster when `file` is absent; absent: the
  /// band described "lethal" (a raster terratraj wrote), else band 1 of `file`.
  std::optional<int> band;
  std::optional<double> max_slope;  ///< [rad] cells steeper than this are lethal
};

/// A terrain: exactly one of `file` and `generate`.
struct TerrainSource {
  std::optional<std::filesystem::path> file;  ///< an elevation raster GDAL reads
  std::optional<GeneratorOptions> generate;   ///< or a generated terrain
  RasterLoadOptions raster;                   ///< cell, z_scale, size limit for `file`
  CoordinateFrame frame = CoordinateFrame::kLocal;
  ObstacleSource obstacles;
  /// The continuous surface built on the heights (`terrain.interpolation`): what every
  /// optimiser, search and check of the problem integrates on.
  Interpolation interpolation = kDefaultInterpolation;
};

/// Builds the terrain a source describes: loads or generates the heights, then adds the lethal
/// cells of `obstacles` (a generated map keeps its own lethal layer too). Throws InputError
/// naming the file or setting at fault.
ElevationMap loadTerrain(const TerrainSource& source);

}  // namespace terratraj::terrain
