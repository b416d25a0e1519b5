#include "terratraj/terrain/elevation_map.hpp"

#include <cmath>
#include <sstream>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::terrain {

ElevationMap::ElevationMap(const GridGeometry& geometry, float fill) : geometry_(geometry) {
  if (geometry.rows < 2 || geometry.cols < 2) {
    std::ostringstream message;
    message << "a terrain needs at least 2 x 2 cells (got " << geometry.cols << " x "
            << geometry.rows << ")";
    throw InputError(message.str());
  }
  if (!(geometry.cell > 0.0) || !std::isfinite(geometry.cell)) {
    std::ostringstream message;
    message << "the cell size must be a positive finite number of metres (got " << geometry.cell
            << ")";
    throw InputError(message.str());
  }
  elevation_ = GridLayer(geometry.rows, geometry.cols, fill);
}

bool ElevationMap::isNoData(CellIndex c) const { return std::isnan(elevation_(c)); }

bool ElevationMap::isLethal(CellIndex c) const {
  const GridLayer* lethal = findLayer(layer_names::kLethal);
  if (lethal == nullptr) return false;
  const float value = (*lethal)(c);
  return value != 0.0f && !std::isnan(value);
}

bool ElevationMap::hasLayer(std::string_view name) const { return findLayer(name) != nullptr; }

const GridLayer* ElevationMap::findLayer(std::string_view name) const {
  if (name == layer_names::kElevation) return &elevation_;
  const auto it = layers_.find(name);
  return it == layers_.end() ? nullptr : &it->second;
}

GridLayer* ElevationMap::findLayer(std::string_view name) {
  return const_cast<GridLayer*>(static_cast<const ElevationMap&>(*this).findLayer(name));
}

GridLayer& ElevationMap::addLayer(const std::string& name, float fill) {
  if (GridLayer* existing = findLayer(name)) return *existing;
  return layers_.emplace(name, GridLayer(geometry_.rows, geometry_.cols, fill)).first->second;
}

std::vector<std::string> ElevationMap::layerNames() const {
  std::vector<std::string> names{layer_names::kElevation};
  for (const auto& entry : layers_) names.push_back(entry.first);
  return names;
}

}  // namespace terratraj::terrain
