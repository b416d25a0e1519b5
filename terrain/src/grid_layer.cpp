#include "terratraj/terrain/grid_layer.hpp"

namespace terratraj::terrain {

GridLayer::GridLayer(int rows, int cols, float fill)
    : rows_(rows), cols_(cols), values_(static_cast<std::size_t>(rows) * cols, fill) {}

}  // namespace terratraj::terrain
