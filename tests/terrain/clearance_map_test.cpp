#include "terratraj/terrain/clearance_map.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/finite_difference.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::terrain {
namespace {

ElevationMap mapWithLethalCells(const std::vector<CellIndex>& cells) {
  GridGeometry geometry;
  geometry.rows = 30;
  geometry.cols = 40;
  geometry.cell = 0.5;
  ElevationMap map(geometry);
  GridLayer& lethal = map.addLayer("lethal");
  for (const CellIndex& c : cells) lethal(c) = 1.0f;
  return map;
}

TEST(ClearanceMap, MatchesBruteForceDistances) {
  const std::vector<CellIndex> obstacles = {{3, 4}, {20, 30}, {10, 10}, {10, 11}, {29, 0}};
  const ElevationMap map = mapWithLethalCells(obstacles);
  const ClearanceMap clearance(map);
  const GridGeometry& g = map.geometry();
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      double best = 1e9;
      for (const CellIndex& o : obstacles) {
        best = std::min(best, g.cell * std::hypot(r - o.row, c - o.col));
      }
      EXPECT_NEAR(clearance.at(g.cellCenter({r, c}))->distance, best - 0.5 * g.cell, 1e-9)
          << r << ", " << c;
    }
  }
}

TEST(ClearanceMap, GradientMatchesDifferencesAndOffMapIsEmpty) {
  const ElevationMap map = mapWithLethalCells({{15, 20}});
  const ClearanceMap clearance(map);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(3.1, 4.2), Eigen::Vector2d(12.3, 9.9)}) {
    const std::optional<Clearance> c = clearance.at(p);
    ASSERT_TRUE(c.has_value());
    const auto distance = [&](const Eigen::VectorXd& at) {
      return Eigen::VectorXd::Constant(1, clearance.at(Eigen::Vector2d(at))->distance);
    };
    EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
        c->gradient.transpose(), terratraj::testing::centralDifferences(distance, p, 1e-6), 1e-6));
  }
  EXPECT_FALSE(clearance.at({-1.0, 2.0}).has_value());
  EXPECT_FALSE(clearance.at({NAN, 2.0}).has_value());
  const ClearanceMap open(mapWithLethalCells({}), 50.0);
  EXPECT_DOUBLE_EQ(open.at({3.0, 3.0})->distance, 50.0);
}

// Beside no data, given a surface's stencil reach, the clearance measures from where that
// surface has no height (bicubic: a 4 x 4 stencil, so the square two cells round the no-data
// cell's centre), not from a band of whole cells: a start on a coarse map, one cell and a bit
// from no data, has a height and a clearance of zero or more (the whole-cell band put it
// inside, and the refiner's clearance row made the problem infeasible at the start).
TEST(ClearanceMap, BesideNoDataMeasuresFromWhereTheSurfaceIsUndefined) {
  ElevationMap map = mapWithLethalCells({});
  map.elevation()(10, 20) = std::nanf("");
  const GridGeometry& g = map.geometry();
  const double h = g.cell;
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const ClearanceMap plain(map);
  const ClearanceMap beside(map, 1e3, surface.stencilReach());
  // The undefined square: the no-data cell's centre (10.25, 5.25) +- 2 cells.
  const Eigen::Vector2d low(10.25 - 2 * h, 5.25 - 2 * h), high(10.25 + 2 * h, 5.25 + 2 * h);
  int defined = 0, undefined = 0;
  for (double x = 7.013; x <= 13.5; x += 0.05) {
    for (double y = 2.013; y <= 8.5; y += 0.05) {
      const Eigen::Vector2d p(x, y);
      const Eigen::Vector2d nearest = p.cwiseMax(low).cwiseMin(high);
      const double outside = (p - nearest).norm();
      const bool inside = outside == 0.0;
      ASSERT_EQ(surface.height(p).has_value(), !inside) << x << ", " << y;
      const double c = beside.at(p)->distance;
      if (inside) {
        ++undefined;
        const double depth = std::min((p - low).minCoeff(), (high - p).minCoeff());
        if (depth > 0.5 * h) {
          EXPECT_LT(c, 0.0) << x << ", " << y;
        }
      } else {
        ++defined;
        EXPECT_NEAR(c, outside, 0.4 * h) << x << ", " << y;  // corners rounded
        if (outside > 0.5 * h) {
          EXPECT_GT(c, 0.0) << x << ", " << y;
        }
      }
      EXPECT_LE(c, plain.at(p)->distance + 1e-12) << x << ", " << y;
    }
  }
  EXPECT_GT(defined, 1000);
  EXPECT_GT(undefined, 1000);
  // Exact at the nodes beside the square, and the gradient is the differences'.
  EXPECT_NEAR(beside.at({11.75, 5.5})->distance, 0.5, 1e-9);
  EXPECT_NEAR(plain.at({11.75, 5.25})->distance, 1.5 - 0.5 * h, 1e-9);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(11.9, 5.6), Eigen::Vector2d(8.3, 3.1)}) {
    const std::optional<Clearance> c = beside.at(p);
    ASSERT_TRUE(c.has_value());
    const auto distance = [&](const Eigen::VectorXd& at) {
      return Eigen::VectorXd::Constant(1, beside.at(Eigen::Vector2d(at))->distance);
    };
    EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
        c->gradient.transpose(), terratraj::testing::centralDifferences(distance, p, 1e-6), 1e-6));
  }
}

}  // namespace
}  // namespace terratraj::terrain
