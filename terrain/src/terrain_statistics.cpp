#include "terratraj/terrain/terrain_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "terratraj/terrain/lethal_layer.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::terrain {

TerrainStatistics computeTerrainStatistics(const ElevationMap& map) {
  TerrainStatistics stats;
  stats.geometry = map.geometry();
  const GridGeometry& g = map.geometry();
  double min_height = std::numeric_limits<double>::infinity();
  double max_height = -std::numeric_limits<double>::infinity();
  double height_sum = 0.0;
  std::vector<double> slopes;
  slopes.reserve(g.cellCount());
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const double z = map.elevation()(r, c);
      if (std::isnan(z)) {
        ++stats.no_data_cells;
        continue;
      }
      ++stats.valid_cells;
      min_height = std::min(min_height, z);
      max_height = std::max(max_height, z);
      height_sum += z;
      if (const auto gradient = cellGradient(map, {r, c})) {
        slopes.push_back(std::atan(gradient->norm()));
      }
    }
  }
  if (stats.valid_cells > 0) {
    stats.min_height = min_height;
    stats.max_height = max_height;
    stats.mean_height = height_sum / static_cast<double>(stats.valid_cells);
  }
  if (!slopes.empty()) {
    double slope_sum = 0.0;
    for (const double s : slopes) slope_sum += s;
    stats.mean_slope = slope_sum / static_cast<double>(slopes.size());
    const std::size_t rank =
        static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(slopes.size()))) - 1;
    std::nth_element(slopes.begin(), slopes.begin() + static_cast<std::ptrdiff_t>(rank),
                     slopes.end());
    stats.p95_slope = slopes[rank];
    stats.max_slope = *std::max_element(slopes.begin(), slopes.end());
  }
  stats.lethal_cells = countLethalCells(map);
  stats.obstacle_clusters = findObstacleClusters(map).size();
  return stats;
}

void computeDerivedLayers(ElevationMap& map) {
  const GridGeometry& g = map.geometry();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  GridLayer& slope = map.addLayer(layer_names::kSlope, nan);
  GridLayer& nx = map.addLayer(layer_names::kNormalX, nan);
  GridLayer& ny = map.addLayer(layer_names::kNormalY, nan);
  GridLayer& nz = map.addLayer(layer_names::kNormalZ, nan);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const std::optional<Eigen::Vector2d> gradient = cellGradient(map, {r, c});
      if (!gradient) {
        slope(r, c) = nx(r, c) = ny(r, c) = nz(r, c) = nan;
        continue;
      }
      const HeightSample sample{0.0, *gradient};
      const Eigen::Vector3d normal = sample.normal();
      slope(r, c) = static_cast<float>(sample.slope());
      nx(r, c) = static_cast<float>(normal.x());
      ny(r, c) = static_cast<float>(normal.y());
      nz(r, c) = static_cast<float>(normal.z());
    }
  }
}

}  // namespace terratraj::terrain
