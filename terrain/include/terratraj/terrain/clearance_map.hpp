#pragma once
// ClearanceMap: distance from any point of the map to the nearest impassable cell (lethal, no
// data) and, optionally, to where a terrain surface beside no data is undefined, from exact
// Euclidean distance transforms of the grid (Felzenszwalb & Huttenlocher), interpolated
// bilinearly between their nodes so that it is continuous with a piecewise-smooth gradient: the
// clearance constraint of the optimisers uses it.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// Clearance at a point and its gradient.
struct Clearance {
  double distance = 0.0;                               ///< [m]; <= 0 inside an impassable cell
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  ///< d distance / d (x, y) [m/m]
};

/// Clearance from the impassable cells of one map. Immutable after construction.
class ClearanceMap {
 public:
  /// Distance transform of `map`'s lethal and no-data cells. With `no_data_reach` > 0 (pass
  /// the surface's TerrainSurface::stencilReach()), the smaller of that and the distance to the
  /// region where such a surface is undefined: the squares between four cell centres whose
  /// stencil reaches a no-data cell (exactly where TerrainSurface has no height), so a point
  /// the surface holds has a clearance of about zero or more, and one it does not, about zero
  /// or less (corners rounded by the interpolation); less `contact_reach_m` [m], >= 0, for a
  /// vehicle that reads the surface that far from its reference point
  /// (models::TerrainFollowingModel::contactReach). The clearance of a node is the distance to
  /// the nearest impassable node minus half a cell (about the distance to that cell's or
  /// square's edge), negative inside one. A map with no impassable cell gets `max_distance`
  /// everywhere. Throws std::bad_alloc only.
  explicit ClearanceMap(const ElevationMap& map, double max_distance = 1e3, int no_data_reach = 0,
                        double contact_reach_m = 0.0);

  /// Clearance at a local point [m], bilinear between the nodes (clamped at the borders);
  /// std::nullopt outside the map or for NaN coordinates. Never throws.
  std::optional<Clearance> at(const Eigen::Vector2d& local) const;

  /// Whether the map has any lethal or no-data cell (else every clearance is max_distance).
  bool hasImpassableCells() const { return has_impassable_; }

  const GridGeometry& geometry() const { return geometry_; }

 private:
  GridGeometry geometry_;
  std::vector<double> distance_;   ///< [m] at the cell centres, from lethal and no-data cells
  std::vector<double> undefined_;  ///< [m] at the cell corners, from the undefined surface
  int undefined_rows_ = 0, undefined_cols_ = 0;
  bool has_impassable_ = false;
};

}  // namespace terratraj::terrain
