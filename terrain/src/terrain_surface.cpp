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

// The uniform cubic B-spline's weights of the coefficients (i-1 .. i+2) of one axis at
// fraction t, with their first and second derivatives in t.
struct SplineBasis {
  double w[4];
  double dw[4];
  double d2w[4];
};

SplineBasis bSplineBasis(double t) {
  const double s = 1.0 - t;
  const double t2 = t * t;
  const double t3 = t2 * t;
  return {{s * s * s / 6.0, (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
           (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0, t3 / 6.0},
          {-0.5 * s * s, 1.5 * t2 - 2.0 * t, -1.5 * t2 + t + 0.5, 0.5 * t2},
          {s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t}};
}

// One axis of the spline's coefficient at a centre: the quasi-interpolant
// (-before + 8 at - after) / 6, which makes the spline reproduce cubics; the height itself where
// a neighbour is no data (so that the spline needs no more samples than its 4 x 4 support).
double prefiltered(double before, double at, double after) {
  if (std::isnan(before) || std::isnan(after)) return at;
  return (8.0 * at - before - after) / 6.0;
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

// The height at (row, col), continued linearly beyond the grid along each axis through the
// two outermost samples, so that planes are reproduced exactly.
double extrapolatedHeight(const float* heights, int rows, int cols, int row, int col) {
  // `index` beyond [0, count) along one axis, `at(k)` the height at index k of that axis.
  const auto beyond = [](int index, int count, const auto& at) {
    const int edge = index < 0 ? 0 : count - 1;
    const int inner = index < 0 ? 1 : count - 2;
    const double z_edge = at(edge);
    const double z_inner = at(inner);
    return z_edge + std::abs(index - edge) * (z_edge - z_inner);
  };
  if (col < 0 || col >= cols) {
    return beyond(col, cols,
                  [&](int c) { return extrapolatedHeight(heights, rows, cols, row, c); });
  }
  if (row < 0 || row >= rows) {
    return beyond(row, rows,
                  [&](int r) { return extrapolatedHeight(heights, rows, cols, r, col); });
  }
  return heights[static_cast<std::size_t>(row) * cols + col];
}

// The N x N heights from (row0, col0), extrapolated linearly where they leave the grid.
template <int N>
void gatherStencil(const float* heights, int rows, int cols, int row0, int col0,
                   double (&z)[N][N]) {
  if (row0 >= 0 && col0 >= 0 && row0 + N - 1 < rows && col0 + N - 1 < cols) {
    for (int i = 0; i < N; ++i) {
      const float* row = heights + static_cast<std::size_t>(row0 + i) * cols + col0;
      for (int j = 0; j < N; ++j) z[i][j] = row[j];
    }
    return;
  }
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j)
      z[i][j] = extrapolatedHeight(heights, rows, cols, row0 + i, col0 + j);
  }
}

// The spline's coefficient at every centre and at the border of one beyond the grid,
// (rows + 2) x (cols + 2) row-major: along x, then along y, through the linearly extrapolated
// heights. A coefficient depends only on the heights around its own centre (3 x 3), so the
// surface is one C2 spline, and it is NaN only where its own centre is no data.
std::vector<double> bSplineCoefficientGrid(const float* heights, int rows, int cols) {
  const int padded_cols = cols + 2;
  // Along x, for the rows -2 .. rows + 1 (padded by two) and the columns -1 .. cols; the heights
  // read directly inside the grid, extrapolated on its border.
  std::vector<double> along_x(static_cast<std::size_t>(rows + 4) * padded_cols);
  const auto z = [&](int r, int c) { return extrapolatedHeight(heights, rows, cols, r, c); };
  for (int r = -2; r < rows + 2; ++r) {
    double* out = along_x.data() + static_cast<std::size_t>(r + 2) * padded_cols;
    if (r >= 0 && r < rows) {
      const float* row = heights + static_cast<std::size_t>(r) * cols;
      for (int c = 1; c + 1 < cols; ++c) out[c + 1] = prefiltered(row[c - 1], row[c], row[c + 1]);
      for (const int c : {-1, 0, cols - 1, cols}) {
        out[c + 1] = prefiltered(z(r, c - 1), z(r, c), z(r, c + 1));
      }
      continue;
    }
    for (int c = -1; c <= cols; ++c) out[c + 1] = prefiltered(z(r, c - 1), z(r, c), z(r, c + 1));
  }
  std::vector<double> grid(static_cast<std::size_t>(rows + 2) * padded_cols);
  for (int r = -1; r <= rows; ++r) {
    const double* below = along_x.data() + static_cast<std::size_t>(r + 1) * padded_cols;
    const double* at = below + padded_cols;
    const double* above = at + padded_cols;
    double* out = grid.data() + static_cast<std::size_t>(r + 1) * padded_cols;
    for (int j = 0; j < padded_cols; ++j) out[j] = prefiltered(below[j], at[j], above[j]);
  }
  return grid;
}

// The 4 x 4 coefficients from the padded grid's (row, col).
void gatherCoefficients(const std::vector<double>& grid, int padded_cols, int row, int col,
                        double (&c)[4][4]) {
  for (int i = 0; i < 4; ++i) {
    const double* src = grid.data() + static_cast<std::size_t>(row + i) * padded_cols + col;
    for (int j = 0; j < 4; ++j) c[i][j] = src[j];
  }
}

// Height, gradient and Hessian of a tensor-product surface sum_ij wy[i] wx[j] z[i][j], given
// each axis's weights and their first and second derivatives in the fraction, and
// d(fraction)/d(coordinate) per axis [1/m].
template <int N>
SurfaceDerivatives tensorDerivatives(const double (&z)[N][N], const double* wx, const double* dwx,
                                     const double* d2wx, const double* wy, const double* dwy,
                                     const double* d2wy, double du, double dv) {
  double h = 0.0, hx = 0.0, hy = 0.0, hxx = 0.0, hxy = 0.0, hyy = 0.0;
  for (int i = 0; i < N; ++i) {
    double value = 0.0, slope = 0.0, bend = 0.0;
    for (int j = 0; j < N; ++j) {
      value += wx[j] * z[i][j];
      slope += dwx[j] * z[i][j];
      bend += d2wx[j] * z[i][j];
    }
    h += wy[i] * value;
    hx += wy[i] * slope;
    hy += dwy[i] * value;
    hxx += wy[i] * bend;
    hxy += dwy[i] * slope;
    hyy += d2wy[i] * value;
  }
  SurfaceDerivatives d;
  d.height = h;
  d.gradient = Eigen::Vector2d(hx * du, hy * dv);
  d.hessian << hxx * du * du, hxy * du * dv, hxy * du * dv, hyy * dv * dv;
  return d;
}

// Height and gradient of the 4 x 4 tensor-product surface sum_ij wy[i] wx[j] z[i][j] (the
// cheaper half of tensorDerivatives); std::nullopt where a sample is no data.
std::optional<HeightSample> tensorSample(const double (&z)[4][4], const double* wx,
                                         const double* dwx, const double* wy, const double* dwy,
                                         double du, double dv) {
  double height = 0.0, dz_dtx = 0.0, dz_dty = 0.0;
  for (int i = 0; i < 4; ++i) {
    double value = 0.0, slope = 0.0;
    for (int j = 0; j < 4; ++j) {
      value += wx[j] * z[i][j];
      slope += dwx[j] * z[i][j];
    }
    height += wy[i] * value;
    dz_dtx += wy[i] * slope;
    dz_dty += dwy[i] * value;
  }
  return finiteOrNothing(height, dz_dtx * du, dz_dty * dv);
}

}  // namespace

std::optional<Interpolation> parseInterpolation(std::string_view name) {
  if (name == "nearest") return Interpolation::kNearest;
  if (name == "bilinear") return Interpolation::kBilinear;
  if (name == "bicubic") return Interpolation::kBicubic;
  if (name == "bspline") return Interpolation::kCubicBSpline;
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
    case Interpolation::kCubicBSpline:
      return "bspline";
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
    case Interpolation::kCubicBSpline:
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
      inv_cell_(1.0 / map.geometry().cell) {
  if (method_ == Interpolation::kCubicBSpline) {
    coefficients_ =
        std::make_shared<const std::vector<double>>(bSplineCoefficientGrid(heights_, rows_, cols_));
  }
}

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
    case Interpolation::kCubicBSpline:
      return sampleBSpline(x, y);
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
  if (method_ == Interpolation::kCubicBSpline) {
    const SplineBasis wx = bSplineBasis(ax.t);
    const SplineBasis wy = bSplineBasis(ay.t);
    double c[4][4];  // the centres from (ay.index - 1, ax.index - 1): padded (ay.index, ax.index)
    gatherCoefficients(*coefficients_, cols_ + 2, ay.index, ax.index, c);
    d = tensorDerivatives(c, wx.w, wx.dw, wx.d2w, wy.w, wy.dw, wy.d2w, ax.dt_dcoord, ay.dt_dcoord);
  } else {
    const CubicWeights wx = catmullRomWeights(ax.t);
    const CubicWeights wy = catmullRomWeights(ay.t);
    const CubicCurvatures cx = catmullRomCurvatures(ax.t);
    const CubicCurvatures cy = catmullRomCurvatures(ay.t);
    double z[4][4];
    gatherStencil(heights_, rows_, cols_, ay.index - 1, ax.index - 1, z);
    d = tensorDerivatives(z, wx.w, wx.dw, cx.d2w, wy.w, wy.dw, cy.d2w, ax.dt_dcoord, ay.dt_dcoord);
  }
  if (!std::isfinite(d.height) || !d.gradient.allFinite() || !d.hessian.allFinite())
    return std::nullopt;
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
  gatherStencil(heights_, rows_, cols_, ay.index - 1, ax.index - 1, z);
  return tensorSample(z, wx.w, wx.dw, wy.w, wy.dw, ax.dt_dcoord, ay.dt_dcoord);
}

std::optional<HeightSample> TerrainSurface::sampleBSpline(double x, double y) const {
  const AxisPosition ax = locateOnAxis(x, inv_cell_, cols_);
  const AxisPosition ay = locateOnAxis(y, inv_cell_, rows_);
  const SplineBasis wx = bSplineBasis(ax.t);
  const SplineBasis wy = bSplineBasis(ay.t);
  double c[4][4];  // the centres from (ay.index - 1, ax.index - 1): padded (ay.index, ax.index)
  gatherCoefficients(*coefficients_, cols_ + 2, ay.index, ax.index, c);
  return tensorSample(c, wx.w, wx.dw, wy.w, wy.dw, ax.dt_dcoord, ay.dt_dcoord);
}

}  // namespace terratraj::terrain
