#include "terratraj/terrain/elevation_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/lethal_layer.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"
#include "test_maps.hpp"

namespace terratraj::terrain {
namespace {

GridGeometry geometry(int rows, int cols, double cell) {
  GridGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.cell = cell;
  return g;
}

TEST(GridGeometry, ConvertsBetweenCellsAndPositions) {
  GridGeometry g = geometry(4, 5, 2.0);
  g.world_origin = {1000.0, 2000.0};
  EXPECT_DOUBLE_EQ(g.width(), 10.0);
  EXPECT_DOUBLE_EQ(g.height(), 8.0);
  EXPECT_EQ(g.cellCenter({0, 0}), Eigen::Vector2d(1.0, 1.0));
  EXPECT_EQ(g.cellCenter({3, 4}), Eigen::Vector2d(9.0, 7.0));
  EXPECT_EQ(*g.cellAt({9.0, 7.0}), (CellIndex{3, 4}));
  EXPECT_EQ(*g.cellAt({10.0, 8.0}), (CellIndex{3, 4}));  // east/north border: last cell
  EXPECT_EQ(*g.cellAt({0.0, 0.0}), (CellIndex{0, 0}));
  EXPECT_FALSE(g.cellAt({-0.1, 1.0}));
  EXPECT_FALSE(g.cellAt({1.0, 8.1}));
  EXPECT_FALSE(g.cellAt({std::nan(""), 1.0}));
  EXPECT_EQ(g.toWorld({1.0, 2.0}), Eigen::Vector2d(1001.0, 2002.0));
  EXPECT_EQ(g.toLocal({1001.0, 2002.0}), Eigen::Vector2d(1.0, 2.0));
  EXPECT_EQ(g.linearIndex({2, 3}), 13u);
}

TEST(ElevationMap, RejectsDegenerateGeometry) {
  EXPECT_THROW(ElevationMap(geometry(1, 5, 1.0)), InputError);
  EXPECT_THROW(ElevationMap(geometry(5, 5, 0.0)), InputError);
  EXPECT_THROW(ElevationMap(geometry(5, 5, std::nan(""))), InputError);
  EXPECT_NO_THROW(ElevationMap(geometry(2, 2, 0.1)));
}

TEST(ElevationMap, HoldsNamedLayers) {
  ElevationMap map(geometry(3, 4, 1.0), 2.0f);
  EXPECT_TRUE(map.hasLayer("elevation"));
  EXPECT_FALSE(map.hasLayer("lethal"));
  EXPECT_EQ(map.findLayer("lethal"), nullptr);
  EXPECT_FALSE(map.isLethal({1, 1}));
  GridLayer& lethal = map.addLayer("lethal");
  lethal(1, 1) = 1.0f;
  EXPECT_TRUE(map.isLethal({1, 1}));
  EXPECT_FALSE(map.isLethal({1, 2}));
  EXPECT_EQ(&map.addLayer("lethal"), &lethal);  // existing layer kept
  EXPECT_EQ(map.layerNames(), (std::vector<std::string>{"elevation", "lethal"}));
  map.elevation()(0, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(map.isNoData({0, 0}));
  EXPECT_FALSE(map.isNoData({0, 1}));
}

TEST(LethalLayer, MarksCellsSteeperThanTheLimit) {
  // A ramp of 20 degrees along x on the east half, flat on the west half.
  ElevationMap map(geometry(6, 12, 1.0));
  for (int r = 0; r < 6; ++r) {
    for (int c = 6; c < 12; ++c)
      map.elevation()(r, c) = static_cast<float>(std::tan(0.349) * (c - 5));
  }
  const std::size_t marked = markLethalBySlope(map, 15.0 * M_PI / 180.0);
  EXPECT_GT(marked, 0u);
  EXPECT_EQ(countLethalCells(map), marked);
  EXPECT_FALSE(map.isLethal({3, 2}));
  EXPECT_TRUE(map.isLethal({3, 9}));
  EXPECT_EQ(markLethalBySlope(map, 15.0 * M_PI / 180.0), 0u);  // already lethal
  EXPECT_THROW(markLethalBySlope(map, 0.0), InputError);
  EXPECT_THROW(markLethalBySlope(map, M_PI / 2), InputError);
}

TEST(LethalLayer, MergesARasterLayerAndChecksItsSize) {
  ElevationMap map(geometry(4, 4, 1.0));
  GridLayer source(4, 4, 0.0f);
  source(2, 3) = 5.0f;
  source(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(markLethalFromLayer(map, source), 1u);
  EXPECT_TRUE(map.isLethal({2, 3}));
  EXPECT_FALSE(map.isLethal({1, 1}));
  EXPECT_THROW(markLethalFromLayer(map, GridLayer(3, 4, 0.0f)), InputError);
}

TEST(TerrainStatistics, CountsHeightsNoDataAndSlopes) {
  ElevationMap map = testing::planeMap(10, 10, 1.0, 0.1, 0.0, 5.0);
  map.elevation()(0, 0) = std::numeric_limits<float>::quiet_NaN();
  const TerrainStatistics stats = computeTerrainStatistics(map);
  EXPECT_EQ(stats.no_data_cells, 1u);
  EXPECT_EQ(stats.valid_cells, 99u);
  EXPECT_NEAR(stats.min_height, 5.0 + 0.1 * 0.5, 1e-5);  // (1, 0) is still there
  EXPECT_NEAR(stats.max_height, 5.0 + 0.1 * 9.5, 1e-5);
  EXPECT_NEAR(stats.max_slope, std::atan(0.1), 1e-5);
  EXPECT_NEAR(stats.mean_slope, std::atan(0.1), 1e-5);
  EXPECT_EQ(stats.lethal_cells, 0u);
}

TEST(TerrainStatistics, DerivedLayersHoldSlopeAndNormals) {
  ElevationMap map = testing::planeMap(5, 5, 0.5, 0.0, 0.2, 0.0);
  computeDerivedLayers(map);
  const GridLayer& slope = *map.findLayer(layer_names::kSlope);
  const GridLayer& ny = *map.findLayer(layer_names::kNormalY);
  const GridLayer& nz = *map.findLayer(layer_names::kNormalZ);
  EXPECT_NEAR(slope(2, 2), std::atan(0.2), 1e-6);
  EXPECT_NEAR(ny(0, 4), -0.2 / std::sqrt(1.04), 1e-6);
  EXPECT_NEAR(nz(4, 0), 1.0 / std::sqrt(1.04), 1e-6);
}

}  // namespace
}  // namespace terratraj::terrain
