#include "terratraj/terrain/raster_io.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <system_error>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::terrain {
namespace {

void registerGdalDrivers() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// Keeps GDAL's own error printing off stderr while it lives; errors are read back with
// CPLGetLastErrorMsg() and reported through InputError instead.
class QuietGdalErrors {
 public:
  QuietGdalErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdalErrors() { CPLPopErrorHandler(); }
  QuietGdalErrors(const QuietGdalErrors&) = delete;
  QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;

  static std::string lastMessage() {
    const char* message = CPLGetLastErrorMsg();
    return (message != nullptr && *message != '\0') ? std::string(message) : std::string();
  }
};

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw InputError(path.string() + ": " + what);
}

GDALDatasetUniquePtr openRaster(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, error)) fail(path, "is a directory, not a raster file");
  registerGdalDrivers();
  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!dataset) {
    const std::string reason = QuietGdalErrors::lastMessage();
    fail(path,
         "not a raster GDAL can read" + (reason.empty() ? std::string() : " (" + reason + ")"));
  }
  if (dataset->GetRasterCount() < 1) fail(path, "has no raster band");
  return dataset;
}

// The grid a dataset describes, from its geotransform or the `cell` option. The returned
// flag says whether GDAL's row 0 is the northern-most row (the usual case).
struct RasterPlacement {
  GridGeometry geometry;
  bool north_row_first = true;
  bool georeferenced = true;
};

// Whether a raster without georeferencing (and no `cell` option) is an error.
enum class Georeferencing { kRequired, kOptional };

RasterPlacement placeRaster(GDALDataset& dataset, const std::filesystem::path& path,
                            const RasterLoadOptions& options, Georeferencing georeferencing) {
  RasterPlacement placement;
  GridGeometry& g = placement.geometry;
  g.cols = dataset.GetRasterXSize();
  g.rows = dataset.GetRasterYSize();
  if (g.rows < 2 || g.cols < 2) {
    fail(path, "a terrain needs at least 2 x 2 cells (got " + std::to_string(g.cols) + " x " +
                   std::to_string(g.rows) + ")");
  }
  if (g.cellCount() > options.max_cells) {
    std::ostringstream message;
    message << "raster of " << g.cols << " x " << g.rows << " cells is larger than the limit of "
            << options.max_cells << " cells";
    fail(path, message.str());
  }
  if (options.cell && (!(*options.cell > 0.0) || !std::isfinite(*options.cell))) {
    std::ostringstream message;
    message << "cell size must be a positive finite number of metres (got " << *options.cell << ")";
    fail(path, message.str());
  }
  std::array<double, 6> gt{};
  const bool georeferenced = dataset.GetGeoTransform(gt.data()) == CE_None;
  if (!georeferenced) {
    placement.georeferenced = false;
    if (!options.cell && georeferencing == Georeferencing::kOptional) return placement;
    if (!options.cell) {
      fail(path,
           "has no georeferencing: give its cell size in metres (terrain.cell in the problem "
           "file, --cell on the command line)");
    }
    g.cell = *options.cell;
    g.world_origin.setZero();
    return placement;
  }
  if (gt[2] != 0.0 || gt[4] != 0.0) fail(path, "rotated rasters are not supported (north-up only)");
  if (!(gt[1] > 0.0) || gt[5] == 0.0 || !std::isfinite(gt[1]) || !std::isfinite(gt[5])) {
    fail(path, "invalid geotransform pixel size");
  }
  const double cell_x = gt[1];
  const double cell_y = std::abs(gt[5]);
  if (std::abs(cell_x - cell_y) > 1e-6 * cell_x) {
    std::ostringstream message;
    message << "non-square cells (" << cell_x << " x " << cell_y << " m) are not supported";
    fail(path, message.str());
  }
  placement.north_row_first = gt[5] < 0.0;
  const double bottom = placement.north_row_first ? gt[3] + g.rows * gt[5] : gt[3];
  g.world_origin = Eigen::Vector2d(gt[0], bottom);
  g.cell = options.cell.value_or(cell_x);
  return placement;
}

// Reads band `band_index` (from 1) into `layer` (south row first), mapping the no-data value to
// NaN and applying z_scale. Returns the number of cells holding data.
std::size_t readBand(GDALDataset& dataset, const std::filesystem::path& path,
                     const RasterPlacement& placement, double z_scale, GridLayer& layer,
                     int band_index = 1) {
  GDALRasterBand* band = dataset.GetRasterBand(band_index);
  int has_no_data = 0;
  const double no_data = band->GetNoDataValue(&has_no_data);
  const bool no_data_is_nan = has_no_data != 0 && std::isnan(no_data);
  const int rows = placement.geometry.rows;
  const int cols = placement.geometry.cols;
  std::vector<double> buffer(static_cast<std::size_t>(cols));
  std::size_t valid = 0;
  for (int gdal_row = 0; gdal_row < rows; ++gdal_row) {
    if (band->RasterIO(GF_Read, 0, gdal_row, cols, 1, buffer.data(), cols, 1, GDT_Float64, 0, 0) !=
        CE_None) {
      fail(path, "read error at row " + std::to_string(gdal_row) + " (" +
                     QuietGdalErrors::lastMessage() + ")");
    }
    const int row = placement.north_row_first ? rows - 1 - gdal_row : gdal_row;
    for (int col = 0; col < cols; ++col) {
      const double value = buffer[static_cast<std::size_t>(col)];
      if ((has_no_data != 0 && value == no_data) || (no_data_is_nan && std::isnan(value))) {
        layer(row, col) = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      const double scaled = value * z_scale;
      if (!std::isfinite(value) || !std::isfinite(scaled) ||
          std::abs(scaled) > std::numeric_limits<float>::max()) {
        std::ostringstream message;
        message << (band_index == 1 ? "height " : "value ") << value << " at raster row "
                << gdal_row + 1 << ", column " << col + 1 << " (from 1"
                << (band_index == 1 ? "" : ", band " + std::to_string(band_index))
                << ") is not a finite number (declare it as the band's no-data value if it "
                   "marks missing data)";
        fail(path, message.str());
      }
      layer(row, col) = static_cast<float>(scaled);
      ++valid;
    }
  }
  return valid;
}

// The first band (from 1) described `name`, or 0.
int bandDescribed(GDALDataset& dataset, const char* name) {
  for (int b = 1; b <= dataset.GetRasterCount(); ++b) {
    const char* description = dataset.GetRasterBand(b)->GetDescription();
    if (description != nullptr && std::string(description) == name) return b;
  }
  return 0;
}

// GDAL's ESRI ASCII reader turns a cell it cannot parse ("abc", "nan", "inf") into 0 m: every
// cell is checked here first. A cell must be a finite number or the declared NODATA_value.
void checkAsciiGrid(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot be opened for reading");
  std::string token;
  long long cols = 0;
  std::string no_data;
  bool has_no_data = false;
  // The header: key value pairs until the first number.
  std::string first_value;
  while (in >> token) {
    std::string key = token;
    for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool header_key = key == "ncols" || key == "nrows" || key == "xllcorner" ||
                            key == "yllcorner" || key == "xllcenter" || key == "yllcenter" ||
                            key == "cellsize" || key == "dx" || key == "dy" ||
                            key == "nodata_value";
    if (!header_key) {
      first_value = token;
      break;
    }
    std::string value;
    if (!(in >> value)) fail(path, "the header ends after '" + token + "'");
    if (key == "ncols") cols = std::atoll(value.c_str());
    if (key == "nodata_value") {
      no_data = value;
      has_no_data = true;
    }
  }
  if (cols <= 0) return;  // GDAL reports a broken header itself
  char* end = nullptr;
  const double no_data_value = has_no_data ? std::strtod(no_data.c_str(), &end) : 0.0;
  long long index = 0;
  const auto check = [&](const std::string& cell) {
    char* stop = nullptr;
    const double value = std::strtod(cell.c_str(), &stop);
    const bool number = !cell.empty() && stop == cell.c_str() + cell.size();
    const bool declared_no_data =
        has_no_data && (cell == no_data || (number && value == no_data_value));
    if (!declared_no_data && (!number || !std::isfinite(value))) {
      std::ostringstream message;
      message << "cell '" << cell << "' at data row " << index / cols + 1 << ", column "
              << index % cols + 1
              << " is not a finite number (ESRI ASCII grid; a missing value must be the "
                 "header's NODATA_value"
              << (has_no_data ? " " + no_data : std::string()) << ")";
      fail(path, message.str());
    }
    ++index;
  };
  if (!first_value.empty()) check(first_value);
  while (in >> token) check(token);
}

struct RasterContents {
  RasterPlacement placement;
  std::string projection_wkt;
  std::unique_ptr<ElevationMap> map;
  std::size_t valid_cells = 0;
  int lethal_band = 0;              ///< the band described "lethal", 0 if none
  std::unique_ptr<GridLayer> band;  ///< the extra band asked for
};

// Which extra band readRaster() reads besides band 1.
struct ExtraBand {
  std::optional<int> number;    ///< this band (from 1) ...
  bool lethal_by_name = false;  ///< ... else the band described "lethal", if any
};

// Reads band 1 (heights, with z_scale) and the extra band, if any (unscaled).
RasterContents readRaster(const std::filesystem::path& path, const RasterLoadOptions& options,
                          Georeferencing georeferencing, const ExtraBand& extra = {}) {
  QuietGdalErrors quiet;
  if (!std::isfinite(options.z_scale) || options.z_scale == 0.0) {
    std::ostringstream message;
    message << "z_scale must be a finite non-zero number (got " << options.z_scale << ")";
    fail(path, message.str());
  }
  GDALDatasetUniquePtr dataset = openRaster(path);
  GDALDriver* driver = dataset->GetDriver();
  if (driver != nullptr && std::string(driver->GetDescription()) == "AAIGrid") {
    checkAsciiGrid(path);
  }
  RasterContents contents;
  contents.placement = placeRaster(*dataset, path, options, georeferencing);
  const char* wkt = dataset->GetProjectionRef();
  contents.projection_wkt = wkt != nullptr ? wkt : "";
  try {
    contents.map = std::make_unique<ElevationMap>(contents.placement.geometry);
  } catch (const std::bad_alloc&) {
    fail(path, "raster of " + std::to_string(contents.placement.geometry.cellCount()) +
                   " cells is too large to allocate");
  }
  contents.valid_cells =
      readBand(*dataset, path, contents.placement, options.z_scale, contents.map->elevation());
  contents.map->setProjectionWkt(contents.projection_wkt);
  contents.lethal_band = bandDescribed(*dataset, layer_names::kLethal);
  const int band = extra.number                                       ? *extra.number
                   : extra.lethal_by_name && contents.lethal_band > 1 ? contents.lethal_band
                                                                      : 0;
  if (band != 0 || extra.number) {
    if (band < 1 || band > dataset->GetRasterCount()) {
      fail(path, "has no band " + std::to_string(band) + " (it has " +
                     std::to_string(dataset->GetRasterCount()) + ")");
    }
    contents.band = std::make_unique<GridLayer>(contents.placement.geometry.rows,
                                                contents.placement.geometry.cols, 0.0f);
    readBand(*dataset, path, contents.placement, 1.0, *contents.band, band);
  }
  return contents;
}

}  // namespace

ElevationMap loadElevationMap(const std::filesystem::path& path, const RasterLoadOptions& options) {
  // A raster terratraj wrote: its lethal band comes back as the lethal layer.
  RasterContents contents =
      readRaster(path, options, Georeferencing::kRequired, ExtraBand{std::nullopt, true});
  if (contents.valid_cells == 0) fail(path, "holds no valid height (every cell is no-data)");
  if (contents.band) {
    GridLayer& lethal = contents.map->addLayer(layer_names::kLethal, 0.0f);
    for (std::size_t i = 0; i < lethal.size(); ++i) {
      const float value = contents.band->values()[i];
      lethal.values()[i] = value != 0.0f && !std::isnan(value) ? 1.0f : 0.0f;
    }
  }
  return std::move(*contents.map);
}

GridLayer loadLethalRaster(const std::filesystem::path& path, const GridGeometry& geometry,
                           const RasterLoadOptions& options, std::optional<int> band) {
  RasterLoadOptions lethal_options = options;
  lethal_options.z_scale = 1.0;
  const RasterContents contents =
      readRaster(path, lethal_options, Georeferencing::kOptional, ExtraBand{band, true});
  const GridLayer& source = contents.band ? *contents.band : contents.map->elevation();
  GridLayer lethal(geometry.rows, geometry.cols, 0.0f);
  const auto is_lethal = [](float value) { return value != 0.0f && !std::isnan(value); };
  if (source.rows() == geometry.rows && source.cols() == geometry.cols) {
    // Same grid: cell by cell, whatever the georeferencing says.
    for (std::size_t i = 0; i < source.size(); ++i) {
      lethal.values()[i] = is_lethal(source.values()[i]) ? 1.0f : 0.0f;
    }
    return lethal;
  }
  if (!contents.placement.georeferenced) {
    fail(path, "lethal raster has no georeferencing and its size (" +
                   std::to_string(source.cols()) + " x " + std::to_string(source.rows()) +
                   ") differs from the terrain's (" + std::to_string(geometry.cols) + " x " +
                   std::to_string(geometry.rows) + ")");
  }
  // Another grid: nearest lethal cell at each terrain cell centre, in world coordinates.
  const GridGeometry& from = contents.placement.geometry;
  for (int row = 0; row < geometry.rows; ++row) {
    for (int col = 0; col < geometry.cols; ++col) {
      const Eigen::Vector2d world = geometry.toWorld(geometry.cellCenter({row, col}));
      const std::optional<CellIndex> cell = from.cellAt(from.toLocal(world));
      if (cell && is_lethal(source(*cell))) lethal(row, col) = 1.0f;
    }
  }
  return lethal;
}

void saveGeoTiff(const ElevationMap& map, const std::filesystem::path& path) {
  QuietGdalErrors quiet;
  registerGdalDrivers();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (driver == nullptr) fail(path, "GDAL has no GTiff driver");
  const GridGeometry& g = map.geometry();
  const std::vector<std::string> names = map.layerNames();
  GDALDatasetUniquePtr dataset(driver->Create(
      path.string().c_str(), g.cols, g.rows, static_cast<int>(names.size()), GDT_Float32, nullptr));
  if (!dataset) fail(path, "cannot be written (" + QuietGdalErrors::lastMessage() + ")");
  std::array<double, 6> gt{
      g.world_origin.x(), g.cell, 0.0, g.world_origin.y() + g.height(), 0.0, -g.cell};
  dataset->SetGeoTransform(gt.data());
  if (!map.projectionWkt().empty()) dataset->SetProjection(map.projectionWkt().c_str());
  for (std::size_t b = 0; b < names.size(); ++b) {
    GDALRasterBand* band = dataset->GetRasterBand(static_cast<int>(b) + 1);
    band->SetDescription(names[b].c_str());
    if (b == 0) band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
    const GridLayer& layer = *map.findLayer(names[b]);
    for (int row = 0; row < g.rows; ++row) {
      // GDAL's row 0 is the northern-most row.
      float* source = const_cast<float*>(layer.values().data()) +
                      static_cast<std::size_t>(g.rows - 1 - row) * g.cols;
      if (band->RasterIO(GF_Write, 0, row, g.cols, 1, source, g.cols, 1, GDT_Float32, 0, 0) !=
          CE_None) {
        fail(path, "write error (" + QuietGdalErrors::lastMessage() + ")");
      }
    }
  }
  CPLErrorReset();
  dataset.reset();  // flushes and closes the file
  if (CPLGetLastErrorType() >= CE_Failure) {
    fail(path, "write error on close (" + QuietGdalErrors::lastMessage() + ")");
  }
}

}  // namespace terratraj::terrain
