#pragma once
// GridGeometry: the placement of a regular, north-up raster in the local and world frames.
//
// Frames (docs/conventions.md): the local frame has its origin at the lower-left corner of the
// lower-left (south-west) cell, x east, y north, metres. The world frame is the raster's
// georeferenced frame; it differs from the local frame by a translation only (north-up rasters).
// Cells are indexed (row, col) with row 0 the SOUTHERN-most row and col 0 the western-most
// column (the reverse of GDAL's row order). Cell (r, c) covers
// [c * cell, (c + 1) * cell] x [r * cell, (r + 1) * cell] and its sample sits at its centre.

#include <Eigen/Core>
#include <cstddef>
#include <optional>

namespace terratraj::terrain {

/// A cell of a grid: row 0 is the southern-most row, col 0 the western-most column.
struct CellIndex {
  int row = 0;
  int col = 0;
  bool operator==(const CellIndex& other) const { return row == other.row && col == other.col; }
};

/// Size and placement of a raster. Value type; cheap to copy.
struct GridGeometry {
  int rows = 0;                                            ///< cells along y (north)
  int cols = 0;                                            ///< cells along x (east)
  double cell = 1.0;                                       ///< cell edge length [m], > 0
  Eigen::Vector2d world_origin = Eigen::Vector2d::Zero();  ///< world (x, y) of the local origin [m]

  /// Number of cells, rows * cols.
  std::size_t cellCount() const { return static_cast<std::size_t>(rows) * cols; }
  /// Extent along x [m].
  double width() const { return cols * cell; }
  /// Extent along y [m].
  double height() const { return rows * cell; }
  /// Linear index of a cell in row-major order (row 0 first). No bounds check.
  std::size_t linearIndex(CellIndex c) const {
    return static_cast<std::size_t>(c.row) * cols + c.col;
  }
  /// Whether a cell index lies on the grid.
  bool isValid(CellIndex c) const {
    return c.row >= 0 && c.row < rows && c.col >= 0 && c.col < cols;
  }
  /// Whether a local point lies inside the raster's extent (borders included).
  bool contains(const Eigen::Vector2d& local) const {
    return local.x() >= 0.0 && local.y() >= 0.0 && local.x() <= width() && local.y() <= height();
  }
  /// The cell holding a local point; points on the east / north border belong to the last
  /// column / row. std::nullopt outside the extent or for NaN coordinates.
  std::optional<CellIndex> cellAt(const Eigen::Vector2d& local) const;
  /// Local position [m] of a cell's centre.
  Eigen::Vector2d cellCenter(CellIndex c) const {
    return {(c.col + 0.5) * cell, (c.row + 0.5) * cell};
  }
  /// Local -> world coordinates [m].
  Eigen::Vector2d toWorld(const Eigen::Vector2d& local) const { return local + world_origin; }
  /// World -> local coordinates [m].
  Eigen::Vector2d toLocal(const Eigen::Vector2d& world) const { return world - world_origin; }
};

}  // namespace terratraj::terrain
