#include "terratraj/terrain/terrain_surface.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "common/finite_difference.hpp"
#include "test_maps.hpp"

namespace terratraj::terrain {
namespace {

using testing::planeMap;
using testing::smoothMap;

constexpr Interpolation kSmoothMethods[] = {Interpolation::kBilinear, Interpolation::kBicubic,
                                            Interpolation::kCubicBSpline};

// Central finite difference of the surface's height.
Eigen::Vector2d finiteDifferenceGradient(const TerrainSurface& surface, const Eigen::Vector2d& p,
                                         double h) {
  const auto height = [&](const Eigen::VectorXd& at) {
    return Eigen::VectorXd::Constant(1, *surface.height(Eigen::Vector2d(at)));
  };
  return terratraj::testing::centralDifferences(height, p, h).row(0).transpose();
}

TEST(TerrainSurface, AnalyticGradientMatchesFiniteDifferencesEverywhere) {
  const ElevationMap map = smoothMap(40, 50, 0.5);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.3, map.geometry().width() - 0.3);
  std::uniform_real_distribution<double> uy(0.3, map.geometry().height() - 0.3);
  for (const Interpolation method : kSmoothMethods) {
    const TerrainSurface surface(map, method);
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector2d p(ux(rng), uy(rng));
      // Stay clear of cell-centre lines, where bilinear has a kink.
      const double fx = p.x() / 0.5 - 0.5 - std::floor(p.x() / 0.5 - 0.5);
      const double fy = p.y() / 0.5 - 0.5 - std::floor(p.y() / 0.5 - 0.5);
      if (fx < 0.01 || fx > 0.99 || fy < 0.01 || fy > 0.99) continue;
      const HeightSample s = *surface.sample(p);
      const Eigen::Vector2d fd = finiteDifferenceGradient(surface, p, 1e-6);
      EXPECT_NEAR(s.gradient.x(), fd.x(), 1e-6)
          << interpolationName(method) << " at " << p.transpose();
      EXPECT_NEAR(s.gradient.y(), fd.y(), 1e-6)
          << interpolationName(method) << " at " << p.transpose();
    }
  }
}

TEST(TerrainSurface, HessianMatchesFiniteDifferencesOfTheGradient) {
  const ElevationMap map = smoothMap(40, 50, 0.5);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(0.3, map.geometry().width() - 0.3);
  std::uniform_real_distribution<double> uy(0.3, map.geometry().height() - 0.3);
  for (const Interpolation method : kSmoothMethods) {
    const TerrainSurface surface(map, method);
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector2d p(ux(rng), uy(rng));
      const double fx = p.x() / 0.5 - 0.5 - std::floor(p.x() / 0.5 - 0.5);
      const double fy = p.y() / 0.5 - 0.5 - std::floor(p.y() / 0.5 - 0.5);
      if (fx < 0.01 || fx > 0.99 || fy < 0.01 || fy > 0.99) continue;  // inside one cell
      const SurfaceDerivatives d = *surface.sampleWithHessian(p);
      const HeightSample s = *surface.sample(p);
      EXPECT_DOUBLE_EQ(d.height, s.height);
      EXPECT_NEAR((d.gradient - s.gradient).norm(), 0.0, 1e-12);
      const auto gradient = [&](const Eigen::VectorXd& at) {
        return Eigen::VectorXd(surface.sample(Eigen::Vector2d(at))->gradient);
      };
      EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
          d.hessian, terratraj::testing::centralDifferences(gradient, p, 1e-6), 1e-5))
          << interpolationName(method);
      ++checked;
    }
    EXPECT_GT(checked, 1500);
  }
  const TerrainSurface nearest(map, Interpolation::kNearest);
  EXPECT_EQ(nearest.sampleWithHessian({3.3, 4.4})->hessian, Eigen::Matrix2d::Zero());
  EXPECT_FALSE(nearest.sampleWithHessian({-1.0, 4.4}));
}

TEST(TerrainSurface, InterpolatesSamplesExactlyAtCellCentres) {
  const ElevationMap map = smoothMap(12, 9, 0.25);
  for (const Interpolation method :
       {Interpolation::kNearest, Interpolation::kBilinear, Interpolation::kBicubic}) {
    const TerrainSurface surface(map, method);
    for (int r = 0; r < 12; ++r) {
      for (int c = 0; c < 9; ++c) {
        EXPECT_NEAR(*surface.height(map.geometry().cellCenter({r, c})), map.elevation()(r, c),
                    1e-6);
      }
    }
  }
}

TEST(TerrainSurface, ReproducesPlanesExactly) {
  const ElevationMap map = planeMap(10, 12, 0.5, 0.3, -0.2, 4.0);
  for (const Interpolation method : kSmoothMethods) {
    const TerrainSurface surface(map, method);
    // Inside the hull of cell centres (the border band is constant-extended).
    for (double x = 0.3; x < 5.7; x += 0.37) {
      for (double y = 0.3; y < 4.7; y += 0.41) {
        const HeightSample s = *surface.sample({x, y});
        EXPECT_NEAR(s.height, 0.3 * x - 0.2 * y + 4.0, 1e-5);
        EXPECT_NEAR(s.gradient.x(), 0.3, 1e-5);
        EXPECT_NEAR(s.gradient.y(), -0.2, 1e-5);
      }
    }
  }
}

TEST(TerrainSurface, BicubicGradientIsContinuousAcrossCellBoundaries) {
  const ElevationMap map = smoothMap(20, 20, 1.0);
  const TerrainSurface bicubic(map, Interpolation::kBicubic);
  for (int k = 2; k < 18; ++k) {
    const double x = k + 0.5;  // a line of cell centres: a boundary between interpolation cells
    const Eigen::Vector2d left = bicubic.sample({x - 1e-9, 7.3})->gradient;
    const Eigen::Vector2d right = bicubic.sample({x + 1e-9, 7.3})->gradient;
    EXPECT_NEAR(left.x(), right.x(), 1e-6);
    EXPECT_NEAR(left.y(), right.y(), 1e-6);
  }
}

TEST(TerrainSurface, BSplineHessianIsContinuousAcrossCellBoundaries) {
  ElevationMap map = smoothMap(20, 20, 1.0);
  // A no-data cell beside the lines below: the coefficients next to it fall back to the heights,
  // and the surface is still one C2 spline where it is defined.
  map.elevation()(10, 10) = std::numeric_limits<float>::quiet_NaN();
  const TerrainSurface spline(map, Interpolation::kCubicBSpline);
  const TerrainSurface bicubic(map, Interpolation::kBicubic);
  double bicubic_jump = 0.0;
  for (int k = 3; k < 17; ++k) {
    const double x = k + 0.5;  // a line of cell centres: a boundary between interpolation cells
    for (const Eigen::Vector2d& step : {Eigen::Vector2d(1e-9, 0.0), Eigen::Vector2d(0.0, 1e-9)}) {
      const Eigen::Vector2d at = step.x() > 0 ? Eigen::Vector2d(x, 8.3) : Eigen::Vector2d(8.3, x);
      const SurfaceDerivatives before = *spline.sampleWithHessian(at - step);
      const SurfaceDerivatives after = *spline.sampleWithHessian(at + step);
      EXPECT_NEAR((before.gradient - after.gradient).norm(), 0.0, 1e-6) << at.transpose();
      EXPECT_NEAR((before.hessian - after.hessian).norm(), 0.0, 1e-6) << at.transpose();
      bicubic_jump = std::max(bicubic_jump, (bicubic.sampleWithHessian(at - step)->hessian -
                                             bicubic.sampleWithHessian(at + step)->hessian)
                                                .norm());
    }
  }
  EXPECT_GT(bicubic_jump, 1e-3);  // the map is one on which C1 and C2 differ
}

TEST(TerrainSurface, BSplineReproducesCubicsAndStaysNearTheSamples) {
  // z = cubic in x and y: reproduced exactly where the stencil stays on the grid (3 cells in).
  ElevationMap map = planeMap(14, 16, 0.5, 0.0, 0.0, 0.0);
  const auto cubic = [](double x, double y) {
    return 0.02 * x * x * x - 0.1 * x * y + 0.05 * y * y * y - 0.3 * y * y + 0.7 * x;
  };
  for (int r = 0; r < 14; ++r) {
    for (int c = 0; c < 16; ++c) {
      const Eigen::Vector2d p = map.geometry().cellCenter({r, c});
      map.elevation()(r, c) = static_cast<float>(cubic(p.x(), p.y()));
    }
  }
  const TerrainSurface spline(map, Interpolation::kCubicBSpline);
  for (double x = 1.8; x < 6.2; x += 0.23) {
    for (double y = 1.8; y < 5.2; y += 0.29) {
      EXPECT_NEAR(*spline.height({x, y}), cubic(x, y), 2e-5) << x << ", " << y;
    }
  }
  // On a smooth map the spline stays within a millimetre of the samples.
  const ElevationMap smooth = smoothMap(12, 9, 0.25);
  const TerrainSurface on_smooth(smooth, Interpolation::kCubicBSpline);
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 9; ++c) {
      EXPECT_NEAR(*on_smooth.height(smooth.geometry().cellCenter({r, c})), smooth.elevation()(r, c),
                  1e-3);
    }
  }
}

// The spline written another way: sum over the centres of coefficient x the centred cubic
// B-spline kernel per axis, each coefficient the quasi-interpolant of the (linearly
// extrapolated) heights around its centre, the height where a neighbour is no data.
double bSplineReference(const ElevationMap& map, double x, double y) {
  const GridGeometry& g = map.geometry();
  const auto z = [&](int r, int c) {
    const auto along_col = [&](int row) {  // the row's height at column c, extrapolated
      const int edge = std::clamp(c, 0, g.cols - 1);
      const int inner = c < 0 ? 1 : g.cols - 2;
      const double at_edge = map.elevation()(row, edge);
      return c == edge ? at_edge
                       : at_edge + std::abs(c - edge) * (at_edge - map.elevation()(row, inner));
    };
    const int edge = std::clamp(r, 0, g.rows - 1);
    const int inner = r < 0 ? 1 : g.rows - 2;
    return r == edge ? along_col(r)
                     : along_col(edge) + std::abs(r - edge) * (along_col(edge) - along_col(inner));
  };
  const auto quasi = [](double before, double at, double after) {
    return std::isnan(before) || std::isnan(after) ? at : (8.0 * at - before - after) / 6.0;
  };
  const auto along_x = [&](int r, int c) { return quasi(z(r, c - 1), z(r, c), z(r, c + 1)); };
  const auto kernel = [](double d) {
    d = std::abs(d);
    if (d >= 2.0) return 0.0;
    if (d >= 1.0) return (2.0 - d) * (2.0 - d) * (2.0 - d) / 6.0;
    return (4.0 - 6.0 * d * d + 3.0 * d * d * d) / 6.0;
  };
  double sum = 0.0;
  for (int r = -1; r <= g.rows; ++r) {
    for (int c = -1; c <= g.cols; ++c) {
      const double w = kernel(x / g.cell - 0.5 - c) * kernel(y / g.cell - 0.5 - r);
      if (w == 0.0) continue;
      sum += w * quasi(along_x(r - 1, c), along_x(r, c), along_x(r + 1, c));
    }
  }
  return sum;
}

TEST(TerrainSurface, BSplineMatchesItsDefinitionOnTheBorderAndBesideNoData) {
  ElevationMap map = smoothMap(11, 13, 0.5);
  map.elevation()(5, 9) = std::numeric_limits<float>::quiet_NaN();
  const TerrainSurface spline(map, Interpolation::kCubicBSpline);
  const TerrainSurface copy = spline;  // copies share the coefficients
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0.25, 6.25), uy(0.25, 5.25);
  int defined = 0;
  for (int n = 0; n < 400; ++n) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const std::optional<HeightSample> s = copy.sample(p);
    const double reference = bSplineReference(map, p.x(), p.y());
    if (!s) {
      EXPECT_TRUE(std::isnan(reference)) << p.transpose();
      continue;
    }
    ++defined;
    EXPECT_NEAR(s->height, reference, 1e-9) << p.transpose();
    EXPECT_NEAR(spline.sampleWithHessian(p)->height, reference, 1e-9) << p.transpose();
  }
  EXPECT_GT(defined, 300);
}

TEST(TerrainSurface, NearestGradientIsTheGridsCentralDifference) {
  const ElevationMap map = smoothMap(10, 10, 0.5);
  const TerrainSurface nearest(map, Interpolation::kNearest);
  const CellIndex cell{4, 6};
  const HeightSample s =
      *nearest.sample(map.geometry().cellCenter(cell) + Eigen::Vector2d(0.1, -0.1));
  const GridLayer& z = map.elevation();
  EXPECT_DOUBLE_EQ(s.height, z(cell));
  EXPECT_NEAR(s.gradient.x(), (z(4, 7) - z(4, 5)) / 1.0, 1e-12);
  EXPECT_NEAR(s.gradient.y(), (z(5, 6) - z(3, 6)) / 1.0, 1e-12);
}

TEST(TerrainSurface, DefinedOnTheWholeExtentAndNothingOutside) {
  const ElevationMap map = smoothMap(8, 6, 1.0);
  for (const Interpolation method : {Interpolation::kNearest, Interpolation::kBilinear,
                                     Interpolation::kBicubic, Interpolation::kCubicBSpline}) {
    const TerrainSurface surface(map, method);
    // Corners and edges of the extent.
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(6, 8), Eigen::Vector2d(0, 8),
          Eigen::Vector2d(6, 0), Eigen::Vector2d(0.2, 4.0), Eigen::Vector2d(5.9, 7.95)}) {
      EXPECT_TRUE(surface.sample(p).has_value()) << interpolationName(method) << p.transpose();
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(-1e-9, 1), Eigen::Vector2d(6.0001, 1), Eigen::Vector2d(1, 8.5),
          Eigen::Vector2d(nan, 1), Eigen::Vector2d(1, -std::numeric_limits<double>::infinity())}) {
      EXPECT_FALSE(surface.sample(p).has_value()) << interpolationName(method) << p.transpose();
    }
  }
}

TEST(TerrainSurface, BorderBandIsConstantExtended) {
  const ElevationMap map = smoothMap(8, 6, 1.0);
  const TerrainSurface bilinear(map, Interpolation::kBilinear);
  const HeightSample at_centre = *bilinear.sample({0.5, 3.2});
  const HeightSample in_band = *bilinear.sample({0.1, 3.2});
  EXPECT_NEAR(in_band.height, at_centre.height, 1e-12);
  EXPECT_EQ(in_band.gradient.x(), 0.0);
}

TEST(TerrainSurface, NoValueWhereTheStencilTouchesNoData) {
  ElevationMap map = smoothMap(12, 12, 1.0);
  map.elevation()(6, 6) = std::numeric_limits<float>::quiet_NaN();
  const TerrainSurface nearest(map, Interpolation::kNearest);
  const TerrainSurface bilinear(map, Interpolation::kBilinear);
  const TerrainSurface bicubic(map, Interpolation::kBicubic);
  // Inside the no-data cell.
  EXPECT_FALSE(nearest.sample({6.5, 6.5}));
  // Between its centre and a neighbour's: bilinear and bicubic stencils include it.
  EXPECT_FALSE(bilinear.sample({7.0, 7.0}));
  EXPECT_FALSE(bicubic.sample({7.0, 7.0}));
  // Two cells away: bilinear is fine, bicubic's 4 x 4 stencil still sees it.
  EXPECT_TRUE(bilinear.sample({8.0, 8.0}));
  EXPECT_FALSE(bicubic.sample({7.9, 7.9}));
  // The spline needs the same 4 x 4 centres as bicubic (its coefficients beside the hole fall
  // back to the heights): undefined 2 cells away, defined 3 away.
  const TerrainSurface spline(map, Interpolation::kCubicBSpline);
  EXPECT_EQ(spline.stencilReach(), 2);
  EXPECT_FALSE(spline.sample({7.0, 7.0}));
  EXPECT_FALSE(spline.sample({7.9, 7.9}));
  EXPECT_TRUE(spline.sample({9.4, 6.5}));
  // Far away: everything is fine.
  EXPECT_TRUE(bicubic.sample({10.0, 2.0}));
  EXPECT_TRUE(nearest.sample({7.6, 6.5}));
}

TEST(TerrainSurface, NormalAndSlope) {
  const HeightSample s{1.0, Eigen::Vector2d(std::tan(0.3), 0.0)};
  EXPECT_NEAR(s.slope(), 0.3, 1e-12);
  const Eigen::Vector3d n = s.normal();
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n.x(), -std::sin(0.3), 1e-12);
  EXPECT_NEAR(n.z(), std::cos(0.3), 1e-12);
}

TEST(TerrainSurface, ParsesInterpolationNames) {
  EXPECT_EQ(parseInterpolation("bicubic"), Interpolation::kBicubic);
  EXPECT_EQ(parseInterpolation("nearest"), Interpolation::kNearest);
  EXPECT_EQ(parseInterpolation("bspline"), Interpolation::kCubicBSpline);
  EXPECT_STREQ(interpolationName(Interpolation::kCubicBSpline), "bspline");
  EXPECT_EQ(parseInterpolation("cubic"), std::nullopt);
  EXPECT_STREQ(interpolationName(Interpolation::kBilinear), "bilinear");
}

}  // namespace
}  // namespace terratraj::terrain
