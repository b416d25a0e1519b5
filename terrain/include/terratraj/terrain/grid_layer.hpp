#pragma once
// GridLayer: one float value per cell of a grid, row-major with row 0 the southern-most row.

#include <cstddef>
#include <vector>

#include "terratraj/terrain/grid_geometry.hpp"

namespace terratraj::terrain {

/// A dense layer of float values over a grid (NaN allowed: it marks "no data").
class GridLayer {
 public:
  GridLayer() = default;
  /// A rows x cols layer filled with `fill`. Throws std::bad_alloc if it cannot be allocated.
  GridLayer(int rows, int cols, float fill);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  std::size_t size() const { return values_.size(); }

  /// Value of a cell; no bounds check (use GridGeometry::isValid first).
  float operator()(int row, int col) const { return values_[index(row, col)]; }
  float& operator()(int row, int col) { return values_[index(row, col)]; }
  float operator()(CellIndex c) const { return (*this)(c.row, c.col); }
  float& operator()(CellIndex c) { return (*this)(c.row, c.col); }

  /// Raw row-major storage (row 0 = south), for bulk processing and I/O.
  const std::vector<float>& values() const { return values_; }
  std::vector<float>& values() { return values_; }

 private:
  std::size_t index(int row, int col) const { return static_cast<std::size_t>(row) * cols_ + col; }

  int rows_ = 0;
  int cols_ = 0;
  std::vector<float> values_;
};

}  // namespace terratraj::terrain
