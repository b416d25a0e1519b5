#include "terratraj/terrain/terrain_source.hpp"

#include <cmath>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/lethal_layer.hpp"

namespace terratraj::terrain {
namespace {

ElevationMap loadHeights(const TerrainSource& source) {
  if (source.file.has_value() == source.generate.has_value()) {
    throw InputError("terrain: give exactly one of file and generate");
  }
  if (source.file) return loadElevationMap(*source.file, source.raster);
  ElevationMap map = generateTerrain(*source.generate);
  if (source.raster.z_scale != 1.0) {
    if (!std::isfinite(source.raster.z_scale) || source.raster.z_scale == 0.0) {
      throw InputError("terrain.z_scale: must be a finite non-zero number");
    }
    for (float& z : map.elevation().values()) z = static_cast<float>(z * source.raster.z_scale);
  }
  return map;
}

}  // namespace

ElevationMap loadTerrain(const TerrainSource& source) {
  ElevationMap map = loadHeights(source);
  RasterLoadOptions lethal_options;
  lethal_options.max_cells = source.raster.max_cells;
  try {
    if (source.obstacles.file) {
      markLethalFromLayer(map, loadLethalRaster(*source.obstacles.file, map.geometry(),
                                                lethal_options, source.obstacles.band));
    } else if (source.obstacles.band) {
      if (!source.file) throw InputError("needs terrain.file (a raster)");
      lethal_options.cell = source.raster.cell;
      markLethalFromLayer(map, loadLethalRaster(*source.file, map.geometry(), lethal_options,
                                                source.obstacles.band));
    }
  } catch (const InputError& error) {
    throw InputError(std::string("terrain.obstacles") +
                     (source.obstacles.band ? ".band" : ".file") + ": " + error.what());
  }
  if (source.obstacles.max_slope) markLethalBySlope(map, *source.obstacles.max_slope);
  return map;
}

}  // namespace terratraj::terrain
