#pragma once
// ElevationMap: a raster of terrain heights with its geometry and named float layers.
//
// Heights are in metres in the layer "elevation"; NaN marks no-data cells. Other layers share
// the geometry: "lethal" (non-zero = the vehicle may not enter the cell), and the derived
// layers "slope" [rad], "normal_x", "normal_y", "normal_z" (computeDerivedLayers()).

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "terratraj/terrain/grid_geometry.hpp"
#include "terratraj/terrain/grid_layer.hpp"

namespace terratraj::terrain {

/// Names of the layers that terratraj itself reads or writes.
namespace layer_names {
inline constexpr const char* kElevation = "elevation";
inline constexpr const char* kLethal = "lethal";
inline constexpr const char* kSlope = "slope";
inline constexpr const char* kNormalX = "normal_x";
inline constexpr const char* kNormalY = "normal_y";
inline constexpr const char* kNormalZ = "normal_z";
}  // namespace layer_names

/// Terrain heights over a regular north-up grid, plus named layers of the same size.
class ElevationMap {
 public:
  ElevationMap() = default;
  /// A map of the given geometry with every height set to `fill` (NaN = no data).
  /// Throws InputError if rows or cols < 2 or cell is not a positive finite number, and
  /// std::bad_alloc if the layer cannot be allocated.
  explicit ElevationMap(const GridGeometry& geometry, float fill = 0.0f);

  const GridGeometry& geometry() const { return geometry_; }
  /// Heights [m]; NaN = no data.
  const GridLayer& elevation() const { return elevation_; }
  GridLayer& elevation() { return elevation_; }
  /// Whether a cell holds no height (NaN).
  bool isNoData(CellIndex c) const;
  /// Whether a cell is lethal: its "lethal" layer value is non-zero (false without that layer).
  bool isLethal(CellIndex c) const;

  /// Whether a layer of that name exists ("elevation" always does).
  bool hasLayer(std::string_view name) const;
  /// A layer by name; nullptr if absent.
  const GridLayer* findLayer(std::string_view name) const;
  GridLayer* findLayer(std::string_view name);
  /// The layer `name`, created filled with `fill` if absent (existing values are kept).
  GridLayer& addLayer(const std::string& name, float fill = 0.0f);
  /// Names of all layers, "elevation" first.
  std::vector<std::string> layerNames() const;

  /// Coordinate reference system of the world frame as WKT ("" if unknown).
  const std::string& projectionWkt() const { return projection_wkt_; }
  void setProjectionWkt(std::string wkt) { projection_wkt_ = std::move(wkt); }

 private:
  GridGeometry geometry_;
  GridLayer elevation_;
  std::map<std::string, GridLayer, std::less<>> layers_;
  std::string projection_wkt_;
};

}  // namespace terratraj::terrain
