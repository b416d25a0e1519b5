#pragma once
// Small maps shared by the terrain tests.

#include <algorithm>
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

/// Raises on `map` a ridge along x = `x0` [m], `height` [m] high with a Gaussian cross-section
/// of standard deviation `width` [m] (flanks up to 0.61 height / width steep), from the map's
/// southern edge to `gap_y` [m], where it fades out over `fade` [m] (smoothstep): north of
/// gap_y + fade the map is as it was, a gap to go round by.
inline void raiseRidge(ElevationMap& map, double x0, double height, double width, double gap_y,
                       double fade) {
  const GridGeometry& g = map.geometry();
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      const double t = std::clamp((p.y() - gap_y) / fade, 0.0, 1.0);
      const double along = 1.0 - t * t * (3.0 - 2.0 * t);
      const double across = std::exp(-0.5 * std::pow((p.x() - x0) / width, 2));
      map.elevation()(r, c) += static_cast<float>(height * across * along);
    }
  }
}

/// Path of a file in ../shared/data.
inline std::string sharedData(const std::string& name) {
  return std::string(TERRATRAJ_SHARED_DATA_DIR) + "/" + name;
}

}  // namespace terratraj::terrain::testing
