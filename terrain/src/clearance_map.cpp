#include "terratraj/terrain/clearance_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "terratraj/terrain/no_data_band.hpp"

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

// Squared Euclidean distance, in cells, from every cell centre to the nearest marked one (0 on
// them): the separable transform, along each row and then along each column.
std::vector<double> squaredDistances(const GridGeometry& g,
                                     const std::vector<std::uint8_t>& marked) {
  const int rows = g.rows, cols = g.cols;
  // Larger than any squared distance on the grid: "no marked cell in this line yet".
  const double far =
      4.0 * (static_cast<double>(rows) * rows + static_cast<double>(cols) * cols) + 1.0;
  std::vector<double> squared(g.cellCount(), far);
  for (std::size_t i = 0; i < squared.size(); ++i) {
    if (marked[i] != 0) squared[i] = 0.0;
  }
  const int longest = std::max(rows, cols);
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1);
  std::vector<double> line(static_cast<std::size_t>(longest)), out(line.size());
  for (int r = 0; r < rows; ++r) {  // along each row
    double* row = squared.data() + static_cast<std::size_t>(r) * cols;
    std::copy(row, row + cols, line.begin());
    transform1d(line.data(), cols, row, v, z);
  }
  for (int c = 0; c < cols; ++c) {  // then along each column
    for (int r = 0; r < rows; ++r)
      line[static_cast<std::size_t>(r)] = squared[g.linearIndex({r, c})];
    transform1d(line.data(), rows, out.data(), v, z);
    for (int r = 0; r < rows; ++r)
      squared[g.linearIndex({r, c})] = out[static_cast<std::size_t>(r)];
  }
  return squared;
}

}  // namespace

ClearanceMap::ClearanceMap(const ElevationMap& map, double max_distance, int no_data_reach,
                           double no_data_margin_m)
    : geometry_(map.geometry()) {
  const double h = geometry_.cell;
  distance_.assign(geometry_.cellCount(), max_distance);
  // The impassable cells: lethal and no data, each a square; a point's clearance is about the
  // distance to the nearest one's edge.
  std::vector<std::uint8_t> impassable(geometry_.cellCount(), 0);
  for (int r = 0; r < geometry_.rows; ++r) {
    for (int c = 0; c < geometry_.cols; ++c) {
      const CellIndex cell{r, c};
      if (map.isLethal(cell) || map.isNoData(cell)) {
        impassable[geometry_.linearIndex(cell)] = 1;
        has_impassable_ = true;
      }
    }
  }
  if (!has_impassable_) return;
  const std::vector<double> to_impassable = squaredDistances(geometry_, impassable);
  for (std::size_t i = 0; i < distance_.size(); ++i) {
    distance_[i] = std::min(
        distance_[i], to_impassable[i] == 0.0 ? -0.5 * h : h * (std::sqrt(to_impassable[i]) - 0.5));
  }
  // Where the surface is undefined beside no data: every point whose stencil holds a no-data
  // cell, the square of half-width `no_data_reach` cells around each no-data cell's centre.
  // The band's cell centres are the grid points of those squares, so the distance from a cell
  // centre outside the band to the nearest band centre is its exact distance to the undefined
  // region, and bilinear interpolation between the centres puts the zero on the region's edge.
  // Inside the band the clearance is minus the distance to the nearest centre outside it, plus
  // one cell (zero on the band's edge).
  const std::vector<std::uint8_t> band =
      no_data_reach > 0 ? noDataBand(map, no_data_reach) : std::vector<std::uint8_t>();
  if (band.empty()) return;
  std::vector<std::uint8_t> outside(band.size());
  for (std::size_t i = 0; i < band.size(); ++i) outside[i] = band[i] == 0 ? 1 : 0;
  // The distance is convex, so bilinear interpolation overestimates it, near a square's corner
  // only: by up to 1 - 1/sqrt(2) of the value within half a cell of it, by under 0.15 cell
  // anywhere. The level kept for the margin allows for that, so that a positive clearance is
  // at least `no_data_margin_m` from the region wherever it is read.
  const double offset = no_data_margin_m > 0.0 ? std::min(std::sqrt(2.0) * no_data_margin_m,
                                                          no_data_margin_m + 0.15 * h)
                                               : 0.0;
  const std::vector<double> to_band = squaredDistances(geometry_, band);
  const std::vector<double> to_outside = squaredDistances(geometry_, outside);
  for (std::size_t i = 0; i < distance_.size(); ++i) {
    const double d =
        band[i] != 0 ? -h * (std::sqrt(to_outside[i]) - 1.0) : h * std::sqrt(to_band[i]);
    distance_[i] = std::min(distance_[i], d - offset);
  }
}

std::optional<Clearance> ClearanceMap::at(const Eigen::Vector2d& p) const {
  if (!p.allFinite() || !geometry_.contains(p)) return std::nullopt;
  const double h = geometry_.cell;
  // Coordinates in cell-centre units, clamped so the four centres exist.
  const double gx = std::clamp(p.x() / h - 0.5, 0.0, std::max(0.0, geometry_.cols - 1.0));
  const double gy = std::clamp(p.y() / h - 0.5, 0.0, std::max(0.0, geometry_.rows - 1.0));
  const int c0 = std::min(static_cast<int>(gx), std::max(0, geometry_.cols - 2));
  const int r0 = std::min(static_cast<int>(gy), std::max(0, geometry_.rows - 2));
  const int c1 = std::min(c0 + 1, geometry_.cols - 1), r1 = std::min(r0 + 1, geometry_.rows - 1);
  const double fx = gx - c0, fy = gy - r0;
  const double d00 = cellClearance({r0, c0}), d01 = cellClearance({r0, c1});
  const double d10 = cellClearance({r1, c0}), d11 = cellClearance({r1, c1});
  Clearance out;
  out.distance = (1 - fy) * ((1 - fx) * d00 + fx * d01) + fy * ((1 - fx) * d10 + fx * d11);
  const bool interior_x = p.x() / h - 0.5 > 0.0 && p.x() / h - 0.5 < geometry_.cols - 1.0;
  const bool interior_y = p.y() / h - 0.5 > 0.0 && p.y() / h - 0.5 < geometry_.rows - 1.0;
  out.gradient.x() = interior_x ? ((1 - fy) * (d01 - d00) + fy * (d11 - d10)) / h : 0.0;
  out.gradient.y() = interior_y ? ((1 - fx) * (d10 - d00) + fx * (d11 - d01)) / h : 0.0;
  return out;
}

}  // namespace terratraj::terrain
