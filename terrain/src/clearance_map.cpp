#include "terratraj/terrain/clearance_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terratraj::terrain {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One-dimensional squared distance transform of f (Felzenszwalb & Huttenlocher 2012) into d,
// with unit spacing; every f is finite (cells without an obstacle hold a large value). v, z
// are scratch of size n and n + 1.
void transform1d(const double* f, int n, double* d, std::vector<int>& v, std::vector<double>& z) {
  std::size_t k = 0;
  v[0] = 0;
  z[0] = -kInfinity;
  z[1] = kInfinity;
  const auto intersection = [f](int q, int p) {
    return ((f[q] + static_cast<double>(q) * q) - (f[p] + static_cast<double>(p) * p)) /
           (2.0 * (q - p));
  };
  for (int q = 1; q < n; ++q) {
    double s = intersection(q, v[k]);
    while (s <= z[k]) {
      --k;
      s = intersection(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kInfinity;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double offset = q - v[k];
    d[q] = offset * offset + f[v[k]];
  }
}

// Squared distances (in nodes) of a rows x cols grid of nodes, 0 at the marked ones, turned
// in place into clearances [m]: `spacing` x (distance to the nearest marked node - 1/2),
// capped at max_distance. Throws std::bad_alloc only.
void distanceTransform(std::vector<double>& squared, int rows, int cols, double spacing,
                       double max_distance) {
  const int longest = std::max(rows, cols);
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  std::vector<double> line(static_cast<std::size_t>(longest)), out(line.size());
  for (int r = 0; r < rows; ++r) {  // along each row
    double* row = squared.data() + static_cast<std::size_t>(r) * cols;
    std::copy(row, row + cols, line.begin());
    transform1d(line.data(), cols, row, v, z);
  }
  const auto at = [cols](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };
  for (int c = 0; c < cols; ++c) {  // then along each column
    for (int r = 0; r < rows; ++r) line[static_cast<std::size_t>(r)] = squared[at(r, c)];
    transform1d(line.data(), rows, out.data(), v, z);
    for (int r = 0; r < rows; ++r) squared[at(r, c)] = out[static_cast<std::size_t>(r)];
  }
  for (double& value : squared) {
    const double d = value == 0.0 ? -0.5 * spacing : spacing * (std::sqrt(value) - 0.5);
    value = std::min(d, max_distance);
  }
}

// "Nothing marked in this line yet": larger than any squared distance on a rows x cols grid.
double farFor(int rows, int cols) {
  return 4.0 * (static_cast<double>(rows) * rows + static_cast<double>(cols) * cols) + 1.0;
}

}  // namespace

ClearanceMap::ClearanceMap(const ElevationMap& map, double max_distance, int no_data_reach,
                           double contact_reach_m)
    : geometry_(map.geometry()) {
  const int rows = geometry_.rows, cols = geometry_.cols;
  const double far = farFor(rows, cols);
  std::vector<double> squared(geometry_.cellCount(), far);
  bool any = false, any_no_data = false;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const CellIndex cell{r, c};
      const bool no_data = map.isNoData(cell);
      any_no_data = any_no_data || no_data;
      if (no_data || map.isLethal(cell)) {
        squared[geometry_.linearIndex(cell)] = 0.0;
        any = true;
      }
    }
  }
  has_impassable_ = any;
  if (!any) {
    distance_.assign(geometry_.cellCount(), max_distance);
    return;
  }
  distanceTransform(squared, rows, cols, geometry_.cell, max_distance);
  distance_ = std::move(squared);
  if (!any_no_data || no_data_reach <= 0 || rows < 2 || cols < 2) return;
  // The squares between four cell centres (i, j) .. (i + 1, j + 1) whose stencil (cells
  // i - reach + 1 .. i + reach, likewise j) holds no data: there the surface is undefined.
  undefined_rows_ = rows - 1;
  undefined_cols_ = cols - 1;
  std::vector<double> undefined(static_cast<std::size_t>(undefined_rows_) * undefined_cols_,
                                farFor(undefined_rows_, undefined_cols_));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!map.isNoData({r, c})) continue;
      for (int i = std::max(0, r - no_data_reach);
           i <= std::min(undefined_rows_ - 1, r + no_data_reach - 1); ++i) {
        for (int j = std::max(0, c - no_data_reach);
             j <= std::min(undefined_cols_ - 1, c + no_data_reach - 1); ++j) {
          undefined[static_cast<std::size_t>(i) * undefined_cols_ + j] = 0.0;
        }
      }
    }
  }
  distanceTransform(undefined, undefined_rows_, undefined_cols_, geometry_.cell, max_distance);
  for (double& d : undefined) d -= std::max(0.0, contact_reach_m);
  undefined_ = std::move(undefined);
}

namespace {

// Bilinear interpolation at `p` [m] of `values` on a rows x cols grid of nodes, node (0, 0) at
// `origin` [m], `spacing` apart (clamped at the borders), with the gradient (zero across a
// border).
Clearance interpolateNodes(const std::vector<double>& values, int rows, int cols,
                           const Eigen::Vector2d& origin, double spacing,
                           const Eigen::Vector2d& p) {
  const double ux = (p.x() - origin.x()) / spacing, uy = (p.y() - origin.y()) / spacing;
  const double gx = std::clamp(ux, 0.0, std::max(0.0, cols - 1.0));
  const double gy = std::clamp(uy, 0.0, std::max(0.0, rows - 1.0));
  const int c0 = std::min(static_cast<int>(gx), std::max(0, cols - 2));
  const int r0 = std::min(static_cast<int>(gy), std::max(0, rows - 2));
  const int c1 = std::min(c0 + 1, cols - 1), r1 = std::min(r0 + 1, rows - 1);
  const double fx = gx - c0, fy = gy - r0;
  const auto at = [&](int r, int c) { return values[static_cast<std::size_t>(r) * cols + c]; };
  const double d00 = at(r0, c0), d01 = at(r0, c1), d10 = at(r1, c0), d11 = at(r1, c1);
  Clearance out;
  out.distance = (1 - fy) * ((1 - fx) * d00 + fx * d01) + fy * ((1 - fx) * d10 + fx * d11);
  const bool interior_x = ux > 0.0 && ux < cols - 1.0;
  const bool interior_y = uy > 0.0 && uy < rows - 1.0;
  out.gradient.x() = interior_x ? ((1 - fy) * (d01 - d00) + fy * (d11 - d10)) / spacing : 0.0;
  out.gradient.y() = interior_y ? ((1 - fx) * (d10 - d00) + fx * (d11 - d01)) / spacing : 0.0;
  return out;
}

}  // namespace

std::optional<Clearance> ClearanceMap::at(const Eigen::Vector2d& p) const {
  if (!p.allFinite() || !geometry_.contains(p)) return std::nullopt;
  const double h = geometry_.cell;
  Clearance out = interpolateNodes(distance_, geometry_.rows, geometry_.cols,
                                   Eigen::Vector2d(0.5 * h, 0.5 * h), h, p);
  if (!undefined_.empty()) {
    // The undefined squares' centres are the cell corners (i + 1, j + 1).
    const Clearance surface =
        interpolateNodes(undefined_, undefined_rows_, undefined_cols_, Eigen::Vector2d(h, h), h, p);
    if (surface.distance < out.distance) out = surface;
  }
  return out;
}

}  // namespace terratraj::terrain
