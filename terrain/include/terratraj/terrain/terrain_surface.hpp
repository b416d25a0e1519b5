#pragma once
// TerrainSurface: the continuous surface z = g(x, y) interpolated from an ElevationMap.
//
// Heights live at cell centres. A query at a local point (x, y) [m] returns the height [m] and
// its analytic gradient (dz/dx, dz/dy) [m/m]:
//  - kNearest:  the height of the cell holding the point; the gradient is that cell's
//               central-difference gradient of the grid (one-sided on the border), i.e. the
//               "normal_*" layers of computeDerivedLayers(). (The piecewise-constant surface
//               itself has gradient 0 almost everywhere; this is the useful answer.)
//  - kBilinear: bilinear between the four surrounding centres; C0, gradient exact
//               inside each cell of centres.
//  - kBicubic:  Catmull-Rom (Keys, a = -1/2) cubic convolution over a 4 x 4 stencil; C1, so
//               optimisers see a continuous gradient, but its Hessian jumps at every line of
//               cell centres.
//  - kCubicBSpline: the uniform cubic B-spline whose coefficient at each centre is the local
//               quasi-interpolant (-z[k-1] + 8 z[k] - z[k+1]) / 6 of the heights along each
//               axis (the height itself along an axis where a neighbour is no data). C2: the
//               gradient and Hessian are continuous, so constraints built on the gradient
//               (pitch, roll, slope bounds) have a continuous Jacobian. Reproduces cubic
//               polynomials exactly away from no data; at a cell centre it differs from the
//               sample by -1/36 of the fourth difference of the heights along each axis. Defined
//               where the 4 x 4 centres around the point are (as bicubic). The default
//               (kDefaultInterpolation) for everything that optimises or checks a trajectory.
// Where a stencil reaches beyond the grid, the missing samples are extrapolated linearly from
// the two outermost ones, so that planes are reproduced exactly up to the outermost centres.
// Border: inside the extent but beyond the outermost centres (the half-cell band on each edge)
// the surface is extended as a constant along the outward axis (gradient 0 along it): defined
// and continuous, though not C1 across that line. Nothing is read out of bounds.
// The spline's coefficients are computed once, when the surface is built (a grid of one double
// per cell centre plus a border of one: 8 bytes a cell, twice the heights), so that a query
// reads 4 x 4 of them as bicubic reads 4 x 4 heights. A surface therefore reflects the heights
// the map had when it was built: after changing them, build a new surface (every method).
// Failure: std::nullopt outside the extent [0, width] x [0, height], for NaN coordinates, and
// where the stencil touches a no-data cell (1 cell for nearest, 2 x 2 for bilinear, 4 x 4 for
// bicubic and bspline): a no-data hole is surrounded by a band with no value, never an
// invented height.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// How heights are interpolated between cell centres.
enum class Interpolation { kNearest, kBilinear, kBicubic, kCubicBSpline };

/// The surface the optimisers, the checks and the searches use unless a problem says otherwise
/// (`terrain.interpolation`).
constexpr Interpolation kDefaultInterpolation = Interpolation::kCubicBSpline;

/// Parses "nearest" / "bilinear" / "bicubic" / "bspline".
std::optional<Interpolation> parseInterpolation(std::string_view name);
/// The name parseInterpolation() accepts.
const char* interpolationName(Interpolation method);

/// Height [m] and its gradient (dz/dx, dz/dy) [m/m] at one point.
struct HeightSample {
  double height = 0.0;
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();

  /// Upward unit normal of the surface, (-gx, -gy, 1) / norm.
  Eigen::Vector3d normal() const;
  /// Slope angle [rad] = atan(|gradient|).
  double slope() const;
};

/// Height [m], gradient [m/m] and Hessian [1/m] (d2z/dx2, d2z/dxdy; d2z/dydx, d2z/dy2).
/// The Hessian is that of the interpolant inside an interpolation cell: 0 for nearest, only the
/// cross term for bilinear, the full cubic's for bicubic (discontinuous across cells: the
/// bicubic surface is C1, not C2) and for bspline (continuous: C2).
struct SurfaceDerivatives {
  double height = 0.0;
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();
};

/// Read-only view of an ElevationMap as a surface. Cheap to copy (copies share the spline's
/// coefficients); the map must outlive it, and a change to its heights needs a new surface.
class TerrainSurface {
 public:
  /// Reads the map's heights; for kCubicBSpline computes the coefficient grid (time and memory
  /// linear in the cells: 13 ms and 8 MB for 1024 x 1024, docs/benchmarks.md). Throws
  /// std::bad_alloc only.
  TerrainSurface(const ElevationMap& map, Interpolation method);

  const ElevationMap& map() const { return *map_; }
  Interpolation method() const { return method_; }

  /// Height and gradient at a local point; std::nullopt off the map or near no data.
  std::optional<HeightSample> sample(const Eigen::Vector2d& local) const;
  /// Height, gradient and Hessian at a local point (same rules as sample()).
  std::optional<SurfaceDerivatives> sampleWithHessian(const Eigen::Vector2d& local) const;
  /// Height only (same rules as sample()).
  std::optional<double> height(const Eigen::Vector2d& local) const;
  /// How many cells beyond the cell holding a point its stencil reads, in rows and in columns
  /// (0 nearest, 1 bilinear, 2 bicubic and bspline): the surface is undefined somewhere in every
  /// cell this close to a no-data cell, and defined everywhere in a cell farther from all of them.
  int stencilReach() const;

 private:
  std::optional<HeightSample> sampleNearest(double x, double y) const;
  std::optional<HeightSample> sampleBilinear(double x, double y) const;
  std::optional<HeightSample> sampleBicubic(double x, double y) const;
  std::optional<HeightSample> sampleBSpline(double x, double y) const;

  const ElevationMap* map_;
  Interpolation method_;
  const float* heights_;
  int rows_;
  int cols_;
  double inv_cell_;
  /// kCubicBSpline: the coefficient of every centre, (rows + 2) x (cols + 2) row-major, the
  /// centre (row, col) at (row + 1, col + 1); NaN where the centre is no data. Null otherwise.
  std::shared_ptr<const std::vector<double>> coefficients_;
};

/// Central-difference gradient of the grid at a cell (one-sided at the border; a no-data
/// neighbour falls back to the one-sided difference). std::nullopt if the cell is no data or
/// both neighbours along an axis are no data.
std::optional<Eigen::Vector2d> cellGradient(const ElevationMap& map, CellIndex cell);

}  // namespace terratraj::terrain
