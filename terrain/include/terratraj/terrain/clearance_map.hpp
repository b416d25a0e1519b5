#pragma once
// ClearanceMap: distance from any point of the map to the nearest impassable cell (lethal, no
// data, optionally the band beside no data where the surface is undefined), from an exact Euclidean
// distance transform of the grid (Felzenszwalb & Huttenlocher), interpolated bilinearly between
// cell centres so that it is continuous with a piecewise-smooth gradient: the clearance constraint
// of the optimisers uses it.

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
  /// Distance transform of `map`'s lethal and no-data cells: the clearance of a cell centre is
  /// the distance to the nearest such cell centre minus half a cell (about the distance to that
  /// cell's edge), negative inside one. With `no_data_reach` > 0 (pass the surface's
  /// stencilReach() to keep an optimiser where the surface is defined), also the distance to
  /// where the surface is undefined beside no data, the square of half-width `no_data_reach`
  /// cells around each no-data cell's centre (exact at the cell centres and on the square's
  /// edges, bilinear between), less a margin [m] for the vehicle's wheels around its
  /// reference point: a positive clearance read anywhere is at least `no_data_margin_m` from
  /// the region (the margin subtracted is up to sqrt(2) times that, for the interpolation's
  /// overestimate near the region's corners). The smaller of the two counts. A map with no
  /// impassable cell gets `max_distance` everywhere. Throws std::bad_alloc only.
  explicit ClearanceMap(const ElevationMap& map, double max_distance = 1e3, int no_data_reach = 0,
                        double no_data_margin_m = 0.0);

  /// Clearance at a local point [m], bilinear between cell centres (clamped at the borders);
  /// std::nullopt outside the map or for NaN coordinates. Never throws.
  std::optional<Clearance> at(const Eigen::Vector2d& local) const;

  /// Whether the map has any lethal or no-data cell (else every clearance is max_distance).
  bool hasImpassableCells() const { return has_impassable_; }

  /// Clearance of a cell centre [m].
  double cellClearance(CellIndex c) const { return distance_[geometry_.linearIndex(c)]; }

  const GridGeometry& geometry() const { return geometry_; }

 private:
  GridGeometry geometry_;
  std::vector<double> distance_;
  bool has_impassable_ = false;
};

}  // namespace terratraj::terrain
