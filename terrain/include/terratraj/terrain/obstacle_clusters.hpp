#pragma once
// Obstacle clusters: 8-connected components of lethal cells, with their centroids, as used by
// the topology-aware lattice (002_... II) to anchor its reference frames.

#include <Eigen/Core>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// One 8-connected set of lethal cells.
struct ObstacleCluster {
  std::vector<CellIndex> cells;                        ///< members, in flood-fill order
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  ///< mean of the cell centres [m, local]
  CellIndex min_cell;                                  ///< south-west corner of the bounding box
  CellIndex max_cell;                                  ///< north-east corner of the bounding box
};

/// The obstacle clusters of the map's "lethal" layer (none without one), ordered by their
/// first cell in row-major order (row 0 = south). Iterative flood fill: no recursion, any size.
std::vector<ObstacleCluster> findObstacleClusters(const ElevationMap& map);

}  // namespace terratraj::terrain
