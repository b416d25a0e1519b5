#pragma once
// Small maps shared by the terrain tests.

#include <cmath>
#include <string>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain::testing {

/// A smooth analytic surface sampled on a grid: z = sin(0.3 x) cos(0.2 y) + 0.05 x y / 10.
inline double smoothHeight(double x, double y) {
  return std::sin(0.3 * x) * std::cos(0.2 * y) + 0.005 * x * y;
}

/// rows x cols map of smoothHeight() at the cell centres.
inline ElevationMap smoothMap(int rows, int cols, double cell) {
  GridGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.cell = cell;
  ElevationMap map(g);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      map.elevation()(r, c) = static_cast<float>(smoothHeight(p.x(), p.y()));
    }
  }
  return map;
}

/// A plane z = a x + b y + z0 sampled at the cell centres.
inline ElevationMap planeMap(int rows, int cols, double cell, double a, double b, double z0) {
  GridGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.cell = cell;
  ElevationMap map(g);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      map.elevation()(r, c) = static_cast<float>(a * p.x() + b * p.y() + z0);
    }
  }
  return map;
}

/// Path of a file in ../shared/data.
inline std::string sharedData(const std::string& name) {
  return std::string(TERRATRAJ_SHARED_DATA_DIR) + "/" + name;
}

}  // namespace terratraj::terrain::testing
