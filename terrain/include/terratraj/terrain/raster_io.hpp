#pragma once
// Reading and writing elevation rasters through GDAL.
//
// Any raster GDAL reads: GeoTIFF, ESRI ASCII grid (.asc), PNG / PGM heightmaps, SRTM .hgt, ...
// Band 1 holds the heights. The geotransform must be north-up (no rotation terms) with square
// cells; GDAL's origin is the top-left corner, terratraj's local origin the bottom-left (see
// grid_geometry.hpp), and rows are flipped on the way in and out. The band's no-data value
// becomes NaN. Every failure throws InputError with a message naming the file.

#include <cstddef>
#include <filesystem>
#include <optional>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// How a raster is turned into an ElevationMap.
struct RasterLoadOptions {
  /// Cell size [m] to use instead of the geotransform's: required for rasters without
  /// georeferencing (PNG, PGM), and rescales a georeferenced one (its world origin is kept).
  std::optional<double> cell;
  /// Multiplies every height (e.g. to keep slopes when rescaling with `cell`, or to turn
  /// 8-bit grey levels into metres). Must be finite and non-zero.
  double z_scale = 1.0;
  /// Largest raster accepted, in cells: a larger one is refused with InputError before any
  /// allocation. 2^28 cells (a 16384 x 16384 grid, 1 GiB of heights) by default.
  std::size_t max_cells = std::size_t{1} << 28;
};

/// Loads band 1 of a raster as heights. A band whose description is "lethal" (what
/// saveGeoTiff() writes for the lethal layer: `terrain generate`, `demo`) comes back as the
/// lethal layer (non-zero = lethal). Throws InputError when the file is missing or not a raster
/// GDAL reads, the geotransform is rotated / non-square / absent (and no `cell` was given), the
/// grid is smaller than 2 x 2 or larger than max_cells, a value is NaN or infinite without
/// being the declared no-data value (and for an ESRI ASCII grid, a cell that is not a number:
/// the message gives the data row and column, from 1), or no cell holds data.
ElevationMap loadElevationMap(const std::filesystem::path& path,
                              const RasterLoadOptions& options = {});

/// Loads a lethal-cell raster (non-zero = lethal; zero and no-data = free) as a layer for a
/// terrain of `geometry`: band `band` (from 1), or when absent the band described "lethal" if
/// there is one (a raster terratraj wrote), else band 1. A raster of the terrain's rows x cols is
/// taken cell by cell; another size is sampled by nearest neighbour at the terrain's cell
/// centres in world coordinates (cells outside it are free), which needs georeferencing.
/// `options.cell` rescales it as for heights; z_scale is ignored. Throws InputError as
/// loadElevationMap() does, and when `band` does not exist.
GridLayer loadLethalRaster(const std::filesystem::path& path, const GridGeometry& geometry,
                           const RasterLoadOptions& options = {},
                           std::optional<int> band = std::nullopt);

/// Writes the map as a Float32 GeoTIFF: band 1 the heights (no-data NaN), then one band per
/// other layer, each band's description its layer name. Throws InputError when the file cannot
/// be written (its message names the path).
void saveGeoTiff(const ElevationMap& map, const std::filesystem::path& path);

}  // namespace terratraj::terrain
