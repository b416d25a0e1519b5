#pragma once
// Summaries of a terrain (`terratraj terrain info`) and its derived layers.

#include <cstddef>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// What `terratraj terrain info` reports. Angles in radians, lengths in metres.
struct TerrainStatistics {
  GridGeometry geometry;
  std::size_t valid_cells = 0;    ///< cells holding a height
  std::size_t no_data_cells = 0;  ///< cells without one (NaN)
  std::size_t lethal_cells = 0;   ///< non-zero cells of the "lethal" layer
  std::size_t obstacle_clusters = 0;
  double min_height = 0.0;  ///< over valid cells
  double max_height = 0.0;
  double mean_height = 0.0;
  double mean_slope = 0.0;  ///< over cells with a central-difference gradient
  double max_slope = 0.0;
  double p95_slope = 0.0;  ///< 95th percentile (nearest rank)
};

/// Computes the statistics of a map. Slopes come from cellGradient().
TerrainStatistics computeTerrainStatistics(const ElevationMap& map);

/// Adds (or overwrites) the derived layers "slope" [rad] and "normal_x/y/z" (upward unit normal)
/// from cellGradient(); NaN where a cell has no gradient.
void computeDerivedLayers(ElevationMap& map);

}  // namespace terratraj::terrain
