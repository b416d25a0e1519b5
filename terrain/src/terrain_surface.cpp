#include "terratraj/terrain/terrain_surface.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::terrain {
namespace {

// Position of a coordinate among the cell centres of one axis: the index of the centre at or
// before it (so that index + 1 exists), the fraction t in [0, 1] toward the next centre, and
// d(t)/d(coordinate) [1/m] (0 in the constant half-cell band beyond the outermost centres).
struct AxisPosition {
  int index;
  double t;
  double dt_dcoord;
};

AxisPosition locateOnAxis(double coord, double inv_cell, int count) {
  double u = coord * inv_cell - 0.5;
  double du = inv_cell;
  const double last = static_cast<double>(count - 1);
  if (u < 0.0) {
    u = 0.0;
    du = 0.0;
  } else if (u > last) {
    u = last;
    du = 0.0;
  }
  const int index = std::min(static_cast<int>(u), count - 2);
  return {index, u - index, du};
}

// Catmull-Rom weights of samples (i-1, i, i+1, i+2) at fraction t, and their derivatives.
struct CubicWeights {
  double w[4];
  double dw[4];
};

// Second derivatives of the Catmull-Rom weights.
struct CubicCurvatures {
  double d2w[4];
};

CubicCurvatures catmullRomCurvatures(double t) {
  return {{0.5 * (4.0 - 6.0 * t), 0.5 * (-10.0 + 18.0 * t), 0.5 * (8.0 - 18.0 * t),
           0.5 * (-2.0 + 6.0 * t)}};
}

CubicWeights catmullRomWeights(double t) {
  const double t2 = t * t;
  const double t3 = t2 * t;
  return {{0.5 * (-t + 2.0 * t2 - t3), 0.5 * (2.0 - 5.0 * t2 + 3.0 * t3),
           0.5 * (t + 4.0 * t2 - 3.0 * t3), 0.5 * (-t2 + t3)},
          {0.5 * (-1.0 + 4.0 * t - 3.0 * t2), 0.5 * (-10.0 * t + 9.0 * t2),
           0.5 * (1.0 + 8.0 * t - 9.0 * t2), 0.5 * (-2.0 * t + 3.0 * t2)}};
}

std::optional<HeightSample> finiteOrNothing(double height, double gx, double gy) {
  if (std::isnan(height) || std::isnan(gx) || std::isnan(gy)) return std::nullopt;
  return HeightSample{height, Eigen::Vector2d(gx, gy)};
}

// One-sided or central difference of heights along one axis at a cell; NaN if impossible.
double axisDifference(const GridLayer& z, CellIndex c, int d_row, int d_col, int count,
                      int position, double cell) {
  const double centre = z(c);
  const bool has_prev = position > 0 && !std::isnan(z(c.row - d_row, c.col - d_col));
  const bool has_next = position < count - 1 && !std::isnan(z(c.row + d_row, c.col + d_col));
  if (has_prev && has_next) {
    return (z(c.row + d_row, c.col + d_col) - z(c.row - d_row, c.col - d_col)) / (2.0 * cell);
  }
  if (has_next) return (z(c.row + d_row, c.col + d_col) - centre) / cell;
  if (has_prev) return (centre - z(c.row - d_row, c.col - d_col)) / cell;
  return std::nan("");
}

}  // namespace

std::optional<Interpolation> parseInterpolation(std::string_view name) {
  if (name == "nearest") return Interpolation::kNearest;
  if (name == "bilinear") return Interpolation::kBilinear;
  if (name == "bicubic") return Interpolation::kBicubic;
  return std::nullopt;
}

const char* interpolationName(Interpolation method) {
  switch (method) {
    case Interpolation::kNearest:
      return "nearest";
    case Interpolation::kBilinear:
      return "bilinear";
    case Interpolation::kBicubic:
      return "bicubic";
  }
  return "unknown";
}

int TerrainSurface::stencilReach() const {
  switch (method_) {
    case Interpolation::kNearest:
      return 0;
    case Interpolation::kBilinear:
      return 1;
    case Interpolation::kBicubic:
      return 2;
  }
  return 2;
}

Eigen::Vector3d HeightSample::normal() const {
  return Eigen::Vector3d(-gradient.x(), -gradient.y(), 1.0).normalized();
}

double HeightSample::slope() const { return std::atan(gradient.norm()); }

std::optional<Eigen::Vector2d> cellGradient(const ElevationMap& map, CellIndex cell) {
  const GridGeometry& g = map.geometry();
  const GridLayer& z = map.elevation();
  if (!g.isValid(cell) || std::isnan(z(cell))) return std::nullopt;
  const double gx = axisDifference(z, cell, 0, 1, g.cols, cell.col, g.cell);
  const double gy = axisDifference(z, cell, 1, 0, g.rows, cell.row, g.cell);
  if (std::isnan(gx) || std::isnan(gy)) return std::nullopt;
  return Eigen::Vector2d(gx, gy);
}

TerrainSurface::TerrainSurface(const ElevationMap& map, Interpolation method)
    : map_(&map),
      method_(method),
      heights_(map.elevation().values().data()),
      rows_(map.geometry().rows),
      cols_(map.geometry().cols),
      inv_cell_(1.0 / map.geometry().cell) {}

std::optional<HeightSample> TerrainSurface::sample(const Eigen::Vector2d& local) const {
  const double x = local.x();
  const double y = local.y();
  const GridGeometry& g = map_->geometry();
  if (!(x >= 0.0 && y >= 0.0 && x <= g.width() && y <= g.height())) return std::nullopt;
  switch (method_) {
    case Interpolation::kNearest:
      return sampleNearest(x, y);
    case Interpolation::kBilinear:
      return sampleBilinear(x, y);
    case Interpolation::kBicubic:
      return sampleBicubic(x, y);
  }
  return std::nullopt;
}

std::optional<SurfaceDerivatives> TerrainSurface::sampleWithHessian(
    const Eigen::Vector2d& local) const {
  const double x = local.x();
  const double y = local.y();
  const GridGeometry& g = map_->geometry();
  if (!(x >= 0.0 && y >= 0.0 && x <= g.width() && y <= g.height())) return std::nullopt;
  if (method_ == Interpolation::kNearest) {
    const std::optional<HeightSample> s = sampleNearest(x, y);
    if (!s) return std::nullopt;
    return SurfaceDerivatives{s->height, s->gradient, Eigen::Matrix2d::Zero()};
  }
  const AxisPosition ax = locateOnAxis(x, inv_cell_, cols_);
  const AxisPosition ay = locateOnAxis(y, inv_cell_, rows_);
  SurfaceDerivatives d;
  if (method_ == Interpolation::kBilinear) {
    const std::optional<HeightSample> s = sampleBilinear(x, y);
    if (!s) return std::nullopt;
    const float* row0 = heights_ + static_cast<std::size_t>(ay.index) * cols_ + ax.index;
    const float* row1 = row0 + cols_;
    const double twist = static_cast<double>(row1[1]) - row1[0] - row0[1] + row0[0];
    d.height = s->height;
    d.gradient = s->gradient;
    d.hessian(0, 1) = d.hessian(1, 0) = twist * ax.dt_dcoord * ay.dt_dcoord;
    return d;
  }
  const CubicWeights wx = catmullRomWeights(ax.t);
  const CubicWeights wy = catmullRomWeights(ay.t);
  const CubicCurvatures cx = catmullRomCurvatures(ax.t);
  const CubicCurvatures cy = catmullRomCurvatures(ay.t);
  double z[4][4];
  gatherStencil(ay.index - 1, ax.index - 1, z);
  double h = 0.0, hx = 0.0, hy = 0.0, hxx = 0.0, hxy = 0.0, hyy = 0.0;
  for (int i = 0; i < 4; ++i) {
    double value = 0.0, slope = 0.0, bend = 0.0;
    for (int j = 0; j < 4; ++j) {
      value += wx.w[j] * z[i][j];
      slope += wx.dw[j] * z[i][j];
      bend += cx.d2w[j] * z[i][j];
    }
    h += wy.w[i] * value;
    hx += wy.w[i] * slope;
    hy += wy.dw[i] * value;
    hxx += wy.w[i] * bend;
    hxy += wy.dw[i] * slope;
    hyy += cy.d2w[i] * value;
  }
  const double du = ax.dt_dcoord, dv = ay.dt_dcoord;
  d.height = h;
  d.gradient = Eigen::Vector2d(hx * du, hy * dv);
  d.hessian << hxx * du * du, hxy * du * dv, hxy * du * dv, hyy * dv * dv;
  if (!std::isfinite(h) || !d.gradient.allFinite() || !d.hessian.allFinite()) return std::nullopt;
  return d;
}

std::optional<double> TerrainSurface::height(const Eigen::Vector2d& local) const {
  const std::optional<HeightSample> s = sample(local);
  if (!s) return std::nullopt;
  return s->height;
}

std::optional<HeightSample> TerrainSurface::sampleNearest(double x, double y) const {
  const CellIndex cell{std::min(static_cast<int>(y * inv_cell_), rows_ - 1),
                       std::min(static_cast<int>(x * inv_cell_), cols_ - 1)};
  const std::optional<Eigen::Vector2d> gradient = cellGradient(*map_, cell);
  if (!gradient) return std::nullopt;
  return HeightSample{heights_[static_cast<std::size_t>(cell.row) * cols_ + cell.col], *gradient};
}

std::optional<HeightSample> TerrainSurface::sampleBilinear(double x, double y) const {
  const AxisPosition ax = locateOnAxis(x, inv_cell_, cols_);
  const AxisPosition ay = locateOnAxis(y, inv_cell_, rows_);
  const float* row0 = heights_ + static_cast<std::size_t>(ay.index) * cols_ + ax.index;
  const float* row1 = row0 + cols_;
  const double z00 = row0[0], z01 = row0[1], z10 = row1[0], z11 = row1[1];
  const double tx = ax.t, ty = ay.t;
  const double bottom = z00 + tx * (z01 - z00);
  const double top = z10 + tx * (z11 - z10);
  const double height = bottom + ty * (top - bottom);
  const double dz_dtx = (1.0 - ty) * (z01 - z00) + ty * (z11 - z10);
  const double dz_dty = top - bottom;
  return finiteOrNothing(height, dz_dtx * ax.dt_dcoord, dz_dty * ay.dt_dcoord);
}

std::optional<HeightSample> TerrainSurface::sampleBicubic(double x, double y) const {
  const AxisPosition ax = locateOnAxis(x, inv_cell_, cols_);
  const AxisPosition ay = locateOnAxis(y, inv_cell_, rows_);
  const CubicWeights wx = catmullRomWeights(ax.t);
  const CubicWeights wy = catmullRomWeights(ay.t);
  double z[4][4];
  gatherStencil(ay.index - 1, ax.index - 1, z);
  double height = 0.0, dz_dtx = 0.0, dz_dty = 0.0;
  for (int i = 0; i < 4; ++i) {
    double value = 0.0, slope = 0.0;
    for (int j = 0; j < 4; ++j) {
      value += wx.w[j] * z[i][j];
      slope += wx.dw[j] * z[i][j];
    }
    height += wy.w[i] * value;
    dz_dtx += wy.w[i] * slope;
    dz_dty += wy.dw[i] * value;
  }
  return finiteOrNothing(height, dz_dtx * ax.dt_dcoord, dz_dty * ay.dt_dcoord);
}

void TerrainSurface::gatherStencil(int row0, int col0, double (&z)[4][4]) const {
  if (row0 >= 0 && col0 >= 0 && row0 + 3 < rows_ && col0 + 3 < cols_) {
    for (int i = 0; i < 4; ++i) {
      const float* row = heights_ + static_cast<std::size_t>(row0 + i) * cols_ + col0;
      for (int j = 0; j < 4; ++j) z[i][j] = row[j];
    }
    return;
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) z[i][j] = extrapolatedHeight(row0 + i, col0 + j);
  }
}

double TerrainSurface::extrapolatedHeight(int row, int col) const {
  // One cell beyond the grid, continue the line through the two outermost samples.
  if (col < 0) return 2.0 * extrapolatedHeight(row, 0) - extrapolatedHeight(row, 1);
  if (col >= cols_) {
    return 2.0 * extrapolatedHeight(row, cols_ - 1) - extrapolatedHeight(row, cols_ - 2);
  }
  if (row < 0) return 2.0 * extrapolatedHeight(0, col) - extrapolatedHeight(1, col);
  if (row >= rows_) {
    return 2.0 * extrapolatedHeight(rows_ - 1, col) - extrapolatedHeight(rows_ - 2, col);
  }
  return heights_[static_cast<std::size_t>(row) * cols_ + col];
}

}  // namespace terratraj::terrain
