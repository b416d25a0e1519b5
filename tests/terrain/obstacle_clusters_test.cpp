#include "terratraj/terrain/obstacle_clusters.hpp"

#include <gtest/gtest.h>

#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::terrain {
namespace {

ElevationMap mapWithLethal(const std::vector<CellIndex>& cells, int rows = 10, int cols = 10) {
  GridGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.cell = 1.0;
  ElevationMap map(g);
  GridLayer& lethal = map.addLayer(layer_names::kLethal);
  for (const CellIndex& c : cells) lethal(c) = 1.0f;
  return map;
}

TEST(ObstacleClusters, NoLethalLayerMeansNoClusters) {
  GridGeometry g;
  g.rows = g.cols = 4;
  EXPECT_TRUE(findObstacleClusters(ElevationMap(g)).empty());
}

TEST(ObstacleClusters, DiagonalNeighboursJoinAndCentroidsAreCellCentreMeans) {
  // A diagonal pair (8-connected: one cluster), and a separate 2 x 1 block.
  const ElevationMap map = mapWithLethal({{1, 1}, {2, 2}, {6, 7}, {6, 8}});
  const std::vector<ObstacleCluster> clusters = findObstacleClusters(map);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_EQ(clusters[0].cells.size(), 2u);
  EXPECT_NEAR(clusters[0].centroid.x(), 2.0, 1e-12);  // centres (1.5, 1.5) and (2.5, 2.5)
  EXPECT_NEAR(clusters[0].centroid.y(), 2.0, 1e-12);
  EXPECT_EQ(clusters[1].cells.size(), 2u);
  EXPECT_NEAR(clusters[1].centroid.x(), 8.0, 1e-12);
  EXPECT_NEAR(clusters[1].centroid.y(), 6.5, 1e-12);
  EXPECT_EQ(clusters[1].min_cell, (CellIndex{6, 7}));
  EXPECT_EQ(clusters[1].max_cell, (CellIndex{6, 8}));
}

TEST(ObstacleClusters, CellsTouchingOnlyAcrossAGapStaySeparate) {
  const ElevationMap map = mapWithLethal({{0, 0}, {0, 2}, {2, 0}});
  EXPECT_EQ(findObstacleClusters(map).size(), 3u);
}

TEST(ObstacleClusters, HugeClusterNeedsNoRecursion) {
  GridGeometry g;
  g.rows = g.cols = 1000;
  ElevationMap map(g);
  map.addLayer(layer_names::kLethal, 1.0f);
  const std::vector<ObstacleCluster> clusters = findObstacleClusters(map);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].cells.size(), 1000000u);
}

TEST(ObstacleClusters, ForestHasManySmallClusters) {
  GeneratorOptions options;
  options.kind = TerrainKind::kForest;
  options.rows = options.cols = 128;
  const std::vector<ObstacleCluster> clusters = findObstacleClusters(generateTerrain(options));
  EXPECT_GT(clusters.size(), 30u);
  for (const ObstacleCluster& c : clusters) EXPECT_LE(c.cells.size(), 20u);
}

}  // namespace
}  // namespace terratraj::terrain
