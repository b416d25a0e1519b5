#pragma once
// noDataBand(): the cells beside no data where a terrain surface is undefined. A surface reads
// a stencil of cells around the one holding a point (TerrainSurface::stencilReach(): 0, 1 or
// 2 cells); within that reach of a no-data cell some points of a cell have no height. On a
// coarse map (a 3 m DEM) the band is metres wide: planners that check the cells a path
// touches, and optimisers that keep a clearance, treat it as impassable.

#include <cstdint>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// Per cell of `map` (row-major, GridGeometry::linearIndex), 1 where a no-data cell lies
/// within `reach` cells along the rows and the columns (the cell itself included), else 0.
/// Empty when the map has no no-data cell. `reach` < 0 is taken as 0. Throws std::bad_alloc
/// only.
std::vector<std::uint8_t> noDataBand(const ElevationMap& map, int reach);

}  // namespace terratraj::terrain
