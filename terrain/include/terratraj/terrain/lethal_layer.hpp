#pragma once
// Building the "lethal" layer: from a raster and/or a maximum slope. Lethal cells are those the
// vehicle may not enter; no-data cells are reported separately (ElevationMap::isNoData) and
// planners treat both as impassable.

#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/grid_layer.hpp"

namespace terratraj::terrain {

/// Marks as lethal every cell whose central-difference slope (cellGradient) exceeds
/// `max_slope` [rad]; existing lethal cells stay lethal. Returns how many cells it marked.
/// Throws InputError unless 0 < max_slope < pi/2.
std::size_t markLethalBySlope(ElevationMap& map, double max_slope);

/// Marks as lethal every cell where `lethal` is non-zero and not NaN (same rows and cols as the
/// map); existing lethal cells stay lethal. Returns how many cells it marked.
/// Throws InputError if the layer's size differs from the map's.
std::size_t markLethalFromLayer(ElevationMap& map, const GridLayer& lethal);

/// Number of lethal cells (0 without a "lethal" layer).
std::size_t countLethalCells(const ElevationMap& map);

}  // namespace terratraj::terrain
