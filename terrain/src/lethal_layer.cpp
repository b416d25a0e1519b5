#include "terratraj/terrain/lethal_layer.hpp"

#include <cmath>
#include <sstream>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::terrain {

std::size_t markLethalBySlope(ElevationMap& map, double max_slope) {
  constexpr double kHalfPi = 1.57079632679489661923;
  if (!(max_slope > 0.0 && max_slope < kHalfPi)) {
    std::ostringstream message;
    message << "maximum slope must lie in (0, 90) degrees (got " << max_slope * 90.0 / kHalfPi
            << " degrees)";
    throw InputError(message.str());
  }
  const double max_gradient = std::tan(max_slope);
  const GridGeometry& g = map.geometry();
  GridLayer& lethal = map.addLayer(layer_names::kLethal, 0.0f);
  std::size_t marked = 0;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const std::optional<Eigen::Vector2d> gradient = cellGradient(map, {r, c});
      if (gradient && gradient->norm() > max_gradient && lethal(r, c) == 0.0f) {
        lethal(r, c) = 1.0f;
        ++marked;
      }
    }
  }
  return marked;
}

std::size_t markLethalFromLayer(ElevationMap& map, const GridLayer& source) {
  const GridGeometry& g = map.geometry();
  if (source.rows() != g.rows || source.cols() != g.cols) {
    std::ostringstream message;
    message << "lethal layer of " << source.cols() << " x " << source.rows()
            << " cells does not match the terrain's " << g.cols << " x " << g.rows;
    throw InputError(message.str());
  }
  GridLayer& lethal = map.addLayer(layer_names::kLethal, 0.0f);
  std::size_t marked = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const float value = source.values()[i];
    if (value != 0.0f && !std::isnan(value) && lethal.values()[i] == 0.0f) {
      lethal.values()[i] = 1.0f;
      ++marked;
    }
  }
  return marked;
}

std::size_t countLethalCells(const ElevationMap& map) {
  const GridLayer* lethal = map.findLayer(layer_names::kLethal);
  if (lethal == nullptr) return 0;
  std::size_t count = 0;
  for (const float value : lethal->values()) count += (value != 0.0f && !std::isnan(value));
  return count;
}

}  // namespace terratraj::terrain
