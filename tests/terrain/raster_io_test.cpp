#include "terratraj/terrain/raster_io.hpp"

#include <gdal_priv.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_source.hpp"
#include "terratraj/terrain/terrain_statistics.hpp"
#include "test_maps.hpp"

namespace terratraj::terrain {
namespace {

using ::testing::HasSubstr;
using testing::sharedData;

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards.
class RasterIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("terratraj_raster_io_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    GDALAllRegister();
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path path(const std::string& name) const { return dir_ / name; }

  // Writes a raster with `values` in GDAL's row order (north row first) through `driver`.
  fs::path writeRaster(const std::string& name, const char* driver, int rows, int cols,
                       const std::vector<double>& values, GDALDataType type,
                       std::optional<std::array<double, 6>> geotransform,
                       std::optional<double> no_data = std::nullopt) const {
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDatasetUniquePtr dataset(mem->Create("", cols, rows, 1, type, nullptr));
    if (geotransform) dataset->SetGeoTransform(geotransform->data());
    GDALRasterBand* band = dataset->GetRasterBand(1);
    if (no_data) band->SetNoDataValue(*no_data);
    std::vector<double> copy = values;
    EXPECT_EQ(
        band->RasterIO(GF_Write, 0, 0, cols, rows, copy.data(), cols, rows, GDT_Float64, 0, 0),
        CE_None);
    GDALDriver* out = GetGDALDriverManager()->GetDriverByName(driver);
    const fs::path file = path(name);
    GDALDatasetUniquePtr written(
        out->CreateCopy(file.string().c_str(), dataset.get(), FALSE, nullptr, nullptr, nullptr));
    EXPECT_TRUE(written != nullptr);
    return file;
  }

  std::string loadError(const fs::path& file, const RasterLoadOptions& options = {}) const {
    try {
      loadElevationMap(file, options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }

  fs::path dir_;
};

// The number of NODATA cells of an ESRI ASCII grid, counted by hand from the text.
std::size_t countAsciiNoData(const std::string& file) {
  std::ifstream in(file);
  std::string key;
  double value = 0, no_data = 0;
  for (int i = 0; i < 6; ++i) {
    in >> key >> value;
    if (key == "NODATA_value") no_data = value;
  }
  std::size_t count = 0;
  while (in >> value) count += (value == no_data);
  return count;
}

TEST_F(RasterIoTest, ReadsTheGullyAsciiGrid) {
  const ElevationMap map = loadElevationMap(sharedData("west_bijou_gully.asc"));
  const GridGeometry& g = map.geometry();
  EXPECT_EQ(g.cols, 43);
  EXPECT_EQ(g.rows, 89);
  EXPECT_DOUBLE_EQ(g.cell, 3.0);
  EXPECT_DOUBLE_EQ(g.world_origin.x(), 559705.0);
  EXPECT_DOUBLE_EQ(g.world_origin.y(), 4380220.0);
  const TerrainStatistics stats = computeTerrainStatistics(map);
  const std::size_t expected_no_data = countAsciiNoData(sharedData("west_bijou_gully.asc"));
  EXPECT_GT(expected_no_data, 100u);
  EXPECT_EQ(stats.no_data_cells, expected_no_data);
  EXPECT_NEAR(stats.min_height, 1680.8, 0.1);
  EXPECT_NEAR(stats.max_height, 1725.4, 0.1);
}

TEST_F(RasterIoTest, FlipsRowsSoThatRowZeroIsSouth) {
  // The first data line of an ESRI ASCII grid is the northern-most row.
  std::ofstream(path("tiny.asc")) << "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\n"
                                     "cellsize 2\nNODATA_value -9999\n1 2 3\n4 5 -9999\n";
  const ElevationMap map = loadElevationMap(path("tiny.asc"));
  EXPECT_FLOAT_EQ(map.elevation()(0, 0), 4.0f);  // south-west
  EXPECT_FLOAT_EQ(map.elevation()(1, 2), 3.0f);  // north-east
  EXPECT_TRUE(map.isNoData({0, 2}));
  EXPECT_EQ(map.geometry().world_origin, Eigen::Vector2d(100.0, 200.0));
}

TEST_F(RasterIoTest, ReadsTheLunarAndAlpineGeoTiffs) {
  const ElevationMap moon = loadElevationMap(sharedData("dem_moon.tif"));
  EXPECT_EQ(moon.geometry().rows, 33);
  EXPECT_EQ(moon.geometry().cols, 33);
  EXPECT_NEAR(moon.geometry().cell, 2.43, 0.01);
  const TerrainStatistics moon_stats = computeTerrainStatistics(moon);
  EXPECT_NEAR(moon_stats.min_height, -212.0, 1.0);
  EXPECT_NEAR(moon_stats.max_height, -205.0, 1.0);
  EXPECT_FALSE(moon.projectionWkt().empty());

  const ElevationMap davos = loadElevationMap(sharedData("davosdorf.tif"));
  EXPECT_EQ(davos.geometry().cellCount(), 559u * 495u);
  EXPECT_NEAR(davos.geometry().cell, 10.0, 1e-6);
}

TEST_F(RasterIoTest, CellAndZScaleRescaleARaster) {
  RasterLoadOptions options;
  options.cell = 0.25;
  options.z_scale = 0.5;
  const ElevationMap map = loadElevationMap(sharedData("dem_moon.tif"), options);
  const ElevationMap plain = loadElevationMap(sharedData("dem_moon.tif"));
  EXPECT_DOUBLE_EQ(map.geometry().cell, 0.25);
  EXPECT_EQ(map.geometry().world_origin, plain.geometry().world_origin);
  EXPECT_FLOAT_EQ(map.elevation()(3, 4), 0.5f * plain.elevation()(3, 4));
}

TEST_F(RasterIoTest, GeoTiffRoundTripKeepsEverything) {
  GeneratorOptions options;
  options.kind = TerrainKind::kObstacles;
  options.rows = 40;
  options.cols = 50;
  options.cell = 0.5;
  ElevationMap map = generateTerrain(options);
  map.elevation()(3, 3) = std::numeric_limits<float>::quiet_NaN();
  saveGeoTiff(map, path("map.tif"));
  const ElevationMap back = loadElevationMap(path("map.tif"));
  EXPECT_EQ(back.geometry().rows, 40);
  EXPECT_EQ(back.geometry().cols, 50);
  EXPECT_DOUBLE_EQ(back.geometry().cell, 0.5);
  EXPECT_TRUE(back.isNoData({3, 3}));
  for (int r = 0; r < 40; ++r) {
    for (int c = 0; c < 50; ++c) {
      if (r == 3 && c == 3) continue;
      ASSERT_EQ(back.elevation()(r, c), map.elevation()(r, c)) << r << "," << c;
    }
  }
  // The lethal layer travels as band 2, named.
  GDALDatasetUniquePtr dataset(GDALDataset::Open(path("map.tif").string().c_str(), GDAL_OF_RASTER));
  ASSERT_EQ(dataset->GetRasterCount(), 2);
  EXPECT_STREQ(dataset->GetRasterBand(2)->GetDescription(), "lethal");
}

TEST_F(RasterIoTest, PngAndPgmHeightmapsNeedACellSize) {
  std::vector<double> grey(6 * 5);
  for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<double>(10 * i % 255);
  for (const auto& [name, driver] : {std::pair{"h.png", "PNG"}, std::pair{"h.pgm", "PNM"}}) {
    const fs::path file = writeRaster(name, driver, 6, 5, grey, GDT_Byte, std::nullopt);
    EXPECT_THAT(loadError(file), HasSubstr("no georeferencing")) << name;
    RasterLoadOptions options;
    options.cell = 0.25;
    options.z_scale = 0.01;
    const ElevationMap map = loadElevationMap(file, options);
    EXPECT_EQ(map.geometry().rows, 6);
    EXPECT_EQ(map.geometry().cols, 5);
    EXPECT_DOUBLE_EQ(map.geometry().cell, 0.25);
    // GDAL row 0 (north) is terratraj row 5.
    EXPECT_FLOAT_EQ(map.elevation()(5, 1), static_cast<float>(grey[1] * 0.01)) << name;
    EXPECT_FLOAT_EQ(map.elevation()(0, 4), static_cast<float>(grey[29] * 0.01)) << name;
  }
}

TEST_F(RasterIoTest, BadFilesGiveClearErrors) {
  EXPECT_THAT(loadError(path("missing.tif")), HasSubstr("missing.tif: no such file"));
  EXPECT_THAT(loadError(dir_), HasSubstr("is a directory"));
  std::ofstream(path("garbage.tif")) << "this is not a raster\n";
  EXPECT_THAT(loadError(path("garbage.tif")), HasSubstr("not a raster GDAL can read"));
}

TEST_F(RasterIoTest, RejectsRastersWithoutValidData) {
  const std::array<double, 6> gt{0, 1, 0, 4, 0, -1};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const fs::path all_no_data = writeRaster(
      "empty.tif", "GTiff", 4, 4, std::vector<double>(16, -9999.0), GDT_Float32, gt, -9999.0);
  EXPECT_THAT(loadError(all_no_data), HasSubstr("no valid height"));
  std::vector<double> with_nan(16, 1.0);
  with_nan[5] = nan;
  const fs::path nan_file = writeRaster("nan.tif", "GTiff", 4, 4, with_nan, GDT_Float32, gt);
  EXPECT_THAT(loadError(nan_file), HasSubstr("is not a finite number"));
  // Declared as the no-data value, NaN is fine.
  const fs::path nan_no_data =
      writeRaster("nan_nd.tif", "GTiff", 4, 4, with_nan, GDT_Float32, gt, nan);
  EXPECT_TRUE(loadElevationMap(nan_no_data).isNoData({2, 1}));
  std::vector<double> with_inf(16, 1.0);
  with_inf[0] = std::numeric_limits<double>::infinity();
  const fs::path inf_file = writeRaster("inf.tif", "GTiff", 4, 4, with_inf, GDT_Float32, gt);
  EXPECT_THAT(loadError(inf_file), HasSubstr("inf"));
}

TEST_F(RasterIoTest, RejectsGeometriesItCannotRepresent) {
  const fs::path rotated = writeRaster("rotated.tif", "GTiff", 4, 4, std::vector<double>(16, 1.0),
                                       GDT_Float32, std::array<double, 6>{0, 1, 0.1, 4, 0, -1});
  EXPECT_THAT(loadError(rotated), HasSubstr("rotated"));
  const fs::path rectangular = writeRaster("rect.tif", "GTiff", 4, 4, std::vector<double>(16, 1.0),
                                           GDT_Float32, std::array<double, 6>{0, 1, 0, 4, 0, -2});
  EXPECT_THAT(loadError(rectangular), HasSubstr("non-square cells"));
  const fs::path single = writeRaster("single.tif", "GTiff", 1, 1, {1.0}, GDT_Float32,
                                      std::array<double, 6>{0, 1, 0, 1, 0, -1});
  EXPECT_THAT(loadError(single), HasSubstr("at least 2 x 2"));
}

TEST_F(RasterIoTest, RefusesRastersLargerThanTheLimitBeforeAllocating) {
  RasterLoadOptions options;
  options.max_cells = 1000;
  EXPECT_THAT(loadError(sharedData("west_bijou_gully.asc"), options),
              HasSubstr("larger than the limit of 1000 cells"));
  options = {};
  options.z_scale = 0.0;
  EXPECT_THAT(loadError(sharedData("west_bijou_gully.asc"), options), HasSubstr("z_scale"));
  options = {};
  options.cell = -1.0;
  EXPECT_THAT(loadError(sharedData("west_bijou_gully.asc"), options), HasSubstr("cell size"));
}

TEST_F(RasterIoTest, ReportsUnwritablePaths) {
  GridGeometry g;
  g.rows = g.cols = 3;
  try {
    saveGeoTiff(ElevationMap(g), dir_ / "no_such_folder" / "x.tif");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("x.tif"));
  }
}

TEST_F(RasterIoTest, TerrainSourceCombinesHeightsAndObstacles) {
  // Lethal raster of the same grid as the gully: one lethal cell in GDAL row 0, column 2.
  std::vector<double> lethal(43 * 89, 0.0);
  lethal[2] = 1.0;
  const fs::path lethal_file =
      writeRaster("lethal.tif", "GTiff", 89, 43, lethal, GDT_Byte, std::nullopt);
  TerrainSource source;
  source.file = sharedData("west_bijou_gully.asc");
  source.obstacles.file = lethal_file;
  source.obstacles.max_slope = 30.0 * M_PI / 180.0;
  const ElevationMap map = loadTerrain(source);
  EXPECT_TRUE(map.isLethal({88, 2}));  // GDAL row 0 = terratraj's northern-most row
  const TerrainStatistics stats = computeTerrainStatistics(map);
  EXPECT_GE(stats.lethal_cells, 1u);

  TerrainSource both;
  both.file = source.file;
  both.generate = GeneratorOptions{};
  EXPECT_THROW(loadTerrain(both), InputError);
  TerrainSource generated;
  generated.generate = GeneratorOptions{TerrainKind::kRamp, 10, 10, 1.0, 1};
  generated.raster.z_scale = 2.0;
  EXPECT_NEAR(loadTerrain(generated).elevation()(0, 1), 2.0 * std::tan(10 * M_PI / 180) * 1.5,
              1e-5);
}

}  // namespace
}  // namespace terratraj::terrain

namespace terratraj::terrain {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path freshFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("terratraj_raster_roundtrip_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// What `terrain generate` writes (heights + lethal band) reads back whole, with no extra key;
// obstacles.band picks a band explicitly, and obstacles.file on such a raster reads its lethal
// band, not its heights.
TEST(RasterRoundTrip, AGeneratedRasterKeepsItsLethalBand) {
  const fs::path dir = freshFolder("generated");
  GeneratorOptions generator;
  generator.kind = TerrainKind::kCorridor;
  generator.rows = generator.cols = 64;
  const ElevationMap generated = generateTerrain(generator);
  const GridLayer* lethal = generated.findLayer(layer_names::kLethal);
  ASSERT_NE(lethal, nullptr);
  std::size_t lethal_cells = 0;
  for (float v : lethal->values()) lethal_cells += v != 0.0f ? 1 : 0;
  ASSERT_GT(lethal_cells, 0u);
  saveGeoTiff(generated, dir / "corridor.tif");

  const ElevationMap back = loadElevationMap(dir / "corridor.tif");
  const GridLayer* read = back.findLayer(layer_names::kLethal);
  ASSERT_NE(read, nullptr);
  EXPECT_EQ(read->values(), lethal->values());

  // obstacles.file on the same raster: its lethal band (every cell lethal with band 1 would be
  // the old trap: heights are non-zero).
  TerrainSource source;
  source.generate = generator;
  source.generate->kind = TerrainKind::kFlat;
  source.obstacles.file = dir / "corridor.tif";
  const ElevationMap flat = loadTerrain(source);
  std::size_t flat_lethal = 0;
  for (float v : flat.findLayer(layer_names::kLethal)->values()) flat_lethal += v != 0.0f;
  EXPECT_EQ(flat_lethal, lethal_cells);

  // obstacles.band of the terrain's own raster.
  TerrainSource banded;
  banded.file = dir / "corridor.tif";
  banded.obstacles.band = 2;
  const ElevationMap with_band = loadTerrain(banded);
  EXPECT_EQ(with_band.findLayer(layer_names::kLethal)->values(), lethal->values());
  banded.obstacles.band = 3;
  try {
    loadTerrain(banded);
    ADD_FAILURE() << "band 3 of a 2-band raster was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("terrain.obstacles.band"));
    EXPECT_THAT(error.what(), HasSubstr("no band 3"));
  }
  fs::remove_all(dir);
}

// An ESRI ASCII grid cell that is not a number (GDAL reads it as 0 m) is refused, naming the
// file, the data row and the column; the declared NODATA_value is not.
TEST(RasterRoundTrip, AsciiGridCellsMustBeNumbers) {
  const fs::path dir = freshFolder("ascii");
  const auto grid = [&](const std::string& cell) {
    std::ofstream out(dir / "grid.asc");
    out << "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n"
        << "1 2 3\n4 " << cell << " 6\n7 8 9\n";
    return dir / "grid.asc";
  };
  for (const char* bad : {"abc", "nan", "inf", "-inf", "1.5x"}) {
    SCOPED_TRACE(bad);
    try {
      loadElevationMap(grid(bad));
      ADD_FAILURE() << "accepted";
    } catch (const InputError& error) {
      EXPECT_THAT(error.what(), HasSubstr("grid.asc"));
      EXPECT_THAT(error.what(), HasSubstr("data row 2, column 2"));
    }
  }
  const ElevationMap ok = loadElevationMap(grid("-9999"));
  EXPECT_TRUE(std::isnan(ok.elevation()(1, 1)));  // row 1 from the south = the middle row
  EXPECT_FLOAT_EQ(ok.elevation()(0, 0), 7.0f);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace terratraj::terrain
