#include "terratraj/terrain/clearance_map.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/finite_difference.hpp"
#include "terratraj/terrain/no_data_band.hpp"

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
      EXPECT_NEAR(clearance.cellClearance({r, c}), best - 0.5 * g.cell, 1e-9) << r << ", " << c;
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

// The band beside no data where a surface is undefined: the cells within `reach` of a no-data
// cell; a clearance map given the reach measures from the band, not from the no-data cell.
TEST(NoDataBand, IsTheSquareWithinReachAndTheClearanceStartsAtIt) {
  ElevationMap map = mapWithLethalCells({});
  EXPECT_TRUE(noDataBand(map, 2).empty());
  map.elevation()(10, 20) = std::nanf("");
  const std::vector<std::uint8_t> band = noDataBand(map, 2);
  const GridGeometry& g = map.geometry();
  ASSERT_EQ(band.size(), g.cellCount());
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const bool inside = std::abs(r - 10) <= 2 && std::abs(c - 20) <= 2;
      EXPECT_EQ(band[g.linearIndex({r, c})] != 0, inside) << r << ", " << c;
    }
  }
  const ClearanceMap plain(map);
  const ClearanceMap banded(map, 1e3, 2);
  EXPECT_NEAR(plain.cellClearance({10, 22}), 2.0 * g.cell - 0.5 * g.cell, 1e-9);
  EXPECT_LE(banded.cellClearance({10, 22}), 0.0);
  // Beyond the band, the distance to the square where the surface is undefined: 3 cells from
  // the band's edge at column 22 (not to the edge of a band cell, half a cell farther).
  EXPECT_NEAR(banded.cellClearance({10, 25}), 3.0 * g.cell, 1e-9);
  EXPECT_NEAR(banded.cellClearance({13, 25}), std::hypot(1.0, 3.0) * g.cell, 1e-9);
  // Zero on the square's edge (the band's outer cell centres), negative inside it, and the
  // margin subtracted.
  EXPECT_NEAR(banded.cellClearance({10, 22}), 0.0, 1e-9);
  EXPECT_NEAR(banded.cellClearance({10, 21}), -g.cell, 1e-9);
  const Eigen::Vector2d between = 0.5 * (g.cellCenter({10, 22}) + g.cellCenter({10, 23}));
  EXPECT_NEAR(banded.at(between)->distance, 0.5 * g.cell, 1e-9);
  // A margin of 0.3 m on 0.5 m cells: 0.3 m plus 0.15 cell for the interpolation near corners.
  const ClearanceMap margined(map, 1e3, 2, 0.3);
  EXPECT_NEAR(margined.cellClearance({10, 25}), 3.0 * g.cell - 0.375, 1e-9);
  EXPECT_NEAR(margined.cellClearance({10, 22}), -0.375, 1e-9);
}

}  // namespace
}  // namespace terratraj::terrain
