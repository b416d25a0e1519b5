#include "terratraj/terrain/obstacle_clusters.hpp"

#include <algorithm>

namespace terratraj::terrain {
namespace {

// Grows one cluster from `seed` over 8-connected lethal cells not yet visited.
ObstacleCluster floodFill(const ElevationMap& map, CellIndex seed, std::vector<char>& visited) {
  const GridGeometry& g = map.geometry();
  ObstacleCluster cluster;
  cluster.min_cell = seed;
  cluster.max_cell = seed;
  std::vector<CellIndex> stack{seed};
  visited[g.linearIndex(seed)] = 1;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  while (!stack.empty()) {
    const CellIndex cell = stack.back();
    stack.pop_back();
    cluster.cells.push_back(cell);
    sum += g.cellCenter(cell);
    cluster.min_cell = {std::min(cluster.min_cell.row, cell.row),
                        std::min(cluster.min_cell.col, cell.col)};
    cluster.max_cell = {std::max(cluster.max_cell.row, cell.row),
                        std::max(cluster.max_cell.col, cell.col)};
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const CellIndex next{cell.row + dr, cell.col + dc};
        if (!g.isValid(next) || visited[g.linearIndex(next)] || !map.isLethal(next)) continue;
        visited[g.linearIndex(next)] = 1;
        stack.push_back(next);
      }
    }
  }
  cluster.centroid = sum / static_cast<double>(cluster.cells.size());
  return cluster;
}

}  // namespace

std::vector<ObstacleCluster> findObstacleClusters(const ElevationMap& map) {
  std::vector<ObstacleCluster> clusters;
  if (!map.hasLayer(layer_names::kLethal)) return clusters;
  const GridGeometry& g = map.geometry();
  std::vector<char> visited(g.cellCount(), 0);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const CellIndex cell{r, c};
      if (!visited[g.linearIndex(cell)] && map.isLethal(cell)) {
        clusters.push_back(floodFill(map, cell, visited));
      }
    }
  }
  return clusters;
}

}  // namespace terratraj::terrain
