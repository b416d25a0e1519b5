#include "terratraj/terrain/terrain_generator.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/lethal_layer.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"

namespace terratraj::terrain {
namespace {

namespace fs = std::filesystem;

GeneratorOptions options(TerrainKind kind, int size = 128, std::uint64_t seed = 1) {
  GeneratorOptions o;
  o.kind = kind;
  o.rows = o.cols = size;
  o.cell = 0.25;
  o.seed = seed;
  return o;
}

std::vector<TerrainKind> allKinds() {
  std::vector<TerrainKind> kinds;
  for (const std::string& name : terrainKindNames()) kinds.push_back(*parseTerrainKind(name));
  return kinds;
}

TEST(TerrainGenerator, NamesTheContractsKinds) {
  for (const char* name :
       {"flat", "ramp", "hill", "hills", "corridor", "obstacles", "dead_end", "forest"}) {
    ASSERT_TRUE(parseTerrainKind(name)) << name;
    EXPECT_STREQ(terrainKindName(*parseTerrainKind(name)), name);
  }
  EXPECT_FALSE(parseTerrainKind("mountains"));
}

TEST(TerrainGenerator, EveryKindWritesARasterGdalReads) {
  const fs::path dir = fs::temp_directory_path() / "terratraj_generator_test";
  fs::create_directories(dir);
  GDALAllRegister();
  for (const TerrainKind kind : allKinds()) {
    const ElevationMap map = generateTerrain(options(kind));
    const fs::path file = dir / (std::string(terrainKindName(kind)) + ".tif");
    saveGeoTiff(map, file);
    GDALDatasetUniquePtr dataset(GDALDataset::Open(file.string().c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(dataset) << terrainKindName(kind);
    EXPECT_EQ(dataset->GetRasterXSize(), 128);
    EXPECT_EQ(dataset->GetRasterYSize(), 128);
    const ElevationMap back = loadElevationMap(file);
    EXPECT_EQ(computeTerrainStatistics(back).valid_cells, 128u * 128u) << terrainKindName(kind);
  }
  fs::remove_all(dir);
}

TEST(TerrainGenerator, SameSeedSameMapOtherSeedOtherMap) {
  for (const TerrainKind kind : {TerrainKind::kHills, TerrainKind::kObstacles, TerrainKind::kForest,
                                 TerrainKind::kCorridor, TerrainKind::kDeadEnd}) {
    const ElevationMap a = generateTerrain(options(kind, 128, 7));
    const ElevationMap b = generateTerrain(options(kind, 128, 7));
    const ElevationMap c = generateTerrain(options(kind, 128, 8));
    EXPECT_EQ(a.elevation().values(), b.elevation().values()) << terrainKindName(kind);
    EXPECT_NE(a.elevation().values(), c.elevation().values()) << terrainKindName(kind);
  }
}

TEST(TerrainGenerator, ShapesAreWhatTheirNamesSay) {
  const TerrainStatistics flat =
      computeTerrainStatistics(generateTerrain(options(TerrainKind::kFlat)));
  EXPECT_EQ(flat.max_height, 0.0);
  const TerrainStatistics ramp =
      computeTerrainStatistics(generateTerrain(options(TerrainKind::kRamp)));
  EXPECT_NEAR(ramp.max_slope, 10.0 * M_PI / 180.0, 1e-4);
  EXPECT_NEAR(ramp.mean_slope, 10.0 * M_PI / 180.0, 1e-4);
  const ElevationMap hill = generateTerrain(options(TerrainKind::kHill));
  EXPECT_GT(hill.elevation()(64, 64), 1.0f);  // peak in the middle
  EXPECT_LT(hill.elevation()(2, 2), 0.01f);
  const TerrainStatistics hills =
      computeTerrainStatistics(generateTerrain(options(TerrainKind::kHills, 256)));
  EXPECT_LT(hills.min_height, -0.3);  // valleys
  EXPECT_GT(hills.max_height, 0.3);   // hills
  EXPECT_GT(hills.p95_slope, 5.0 * M_PI / 180.0);
  EXPECT_LT(hills.p95_slope, 35.0 * M_PI / 180.0);
}

TEST(TerrainGenerator, ObstacleKindsHaveLethalCellsButKeepStartAndGoalFree) {
  for (const TerrainKind kind : {TerrainKind::kCorridor, TerrainKind::kObstacles,
                                 TerrainKind::kDeadEnd, TerrainKind::kForest}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const ElevationMap map = generateTerrain(options(kind, 200, seed));
      const std::size_t lethal = countLethalCells(map);
      EXPECT_GT(lethal, 50u) << terrainKindName(kind);
      EXPECT_LT(lethal, map.geometry().cellCount() / 3) << terrainKindName(kind);
      const auto [start, goal] = standardStartGoal(map.geometry());
      for (const Eigen::Vector2d& p : {start, goal}) {
        for (double dx = -2.5; dx <= 2.5; dx += 0.25) {
          for (double dy = -2.5; dy <= 2.5; dy += 0.25) {
            if (dx * dx + dy * dy > 2.5 * 2.5) continue;
            const auto cell = map.geometry().cellAt(p + Eigen::Vector2d(dx, dy));
            ASSERT_TRUE(cell);
            EXPECT_FALSE(map.isLethal(*cell)) << terrainKindName(kind) << " seed " << seed;
          }
        }
      }
    }
  }
}

TEST(TerrainGenerator, CorridorWallsCanOnlyBeCrossedThroughNarrowGaps) {
  const ElevationMap map = generateTerrain(options(TerrainKind::kCorridor, 256));
  // Some column is almost entirely lethal (a wall), with a gap of a few cells.
  const GridGeometry& g = map.geometry();
  int best_column_lethal = 0;
  for (int c = 0; c < g.cols; ++c) {
    int lethal = 0;
    for (int r = 0; r < g.rows; ++r) lethal += map.isLethal({r, c});
    best_column_lethal = std::max(best_column_lethal, lethal);
  }
  EXPECT_GE(best_column_lethal, g.rows - 8);
  EXPECT_LT(best_column_lethal, g.rows);
}

TEST(TerrainGenerator, ScalesFrom128To1024Cells) {
  for (const int size : {128, 1024}) {
    const ElevationMap map = generateTerrain(options(TerrainKind::kHills, size));
    EXPECT_EQ(map.geometry().rows, size);
    EXPECT_DOUBLE_EQ(map.geometry().width(), size * 0.25);
  }
}

TEST(TerrainGenerator, RejectsBadSizes) {
  GeneratorOptions o = options(TerrainKind::kFlat);
  o.rows = 1;
  EXPECT_THROW(generateTerrain(o), InputError);
  o = options(TerrainKind::kFlat);
  o.cell = 0.0;
  EXPECT_THROW(generateTerrain(o), InputError);
  o = options(TerrainKind::kFlat);
  o.rows = o.cols = 1 << 20;
  EXPECT_THROW(generateTerrain(o), InputError);
}

}  // namespace
}  // namespace terratraj::terrain
