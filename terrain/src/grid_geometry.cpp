#include "terratraj/terrain/grid_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::terrain {

std::optional<CellIndex> GridGeometry::cellAt(const Eigen::Vector2d& local) const {
  if (!contains(local)) return std::nullopt;  // also rejects NaN: every comparison is false
  const int col = std::min(static_cast<int>(std::floor(local.x() / cell)), cols - 1);
  const int row = std::min(static_cast<int>(std::floor(local.y() / cell)), rows - 1);
  return CellIndex{row, col};
}

}  // namespace terratraj::terrain
