#include "terratraj/terrain/no_data_band.hpp"

#include <algorithm>

namespace terratraj::terrain {

std::vector<std::uint8_t> noDataBand(const ElevationMap& map, int reach) {
  const GridGeometry& g = map.geometry();
  reach = std::max(0, reach);
  std::vector<std::uint8_t> no_data(g.cellCount(), 0);
  bool any = false;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      if (map.isNoData({r, c})) {
        no_data[g.linearIndex({r, c})] = 1;
        any = true;
      }
    }
  }
  if (!any) return {};
  // Separable: a dilation along each row, then along each column.
  std::vector<std::uint8_t> across(no_data.size(), 0), band(no_data.size(), 0);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      for (int k = std::max(0, c - reach); k <= std::min(g.cols - 1, c + reach); ++k) {
        if (no_data[g.linearIndex({r, k})] != 0) {
          across[g.linearIndex({r, c})] = 1;
          break;
        }
      }
    }
  }
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      for (int k = std::max(0, r - reach); k <= std::min(g.rows - 1, r + reach); ++k) {
        if (across[g.linearIndex({k, c})] != 0) {
          band[g.linearIndex({r, c})] = 1;
          break;
        }
      }
    }
  }
  return band;
}

}  // namespace terratraj::terrain
