#include "terratraj/terrain/no_data_band.hpp"

#include <algorithm>

namespace terratraj::terrain {
namespace {

// Marks in `to` every cell with a marked cell of `from` within `reach` cells along one axis
// (along the rows: columns c - reach .. c + reach; else rows r - reach .. r + reach).
void dilateAlong(const GridGeometry& g, const std::vector<std::uint8_t>& from, int reach,
                 bool along_rows, std::vector<std::uint8_t>& to) {
  const int count = along_rows ? g.cols : g.rows;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const int at = along_rows ? c : r;
      for (int k = std::max(0, at - reach); k <= std::min(count - 1, at + reach); ++k) {
        const CellIndex other = along_rows ? CellIndex{r, k} : CellIndex{k, c};
        if (from[g.linearIndex(other)] != 0) {
          to[g.linearIndex({r, c})] = 1;
          break;
        }
      }
    }
  }
}

}  // namespace

std::vector<std::uint8_t> noDataBand(const ElevationMap& map, int reach) {
  const GridGeometry& g = map.geometry();
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
  dilateAlong(g, no_data, std::max(0, reach), true, across);
  dilateAlong(g, across, std::max(0, reach), false, band);
  return band;
}

}  // namespace terratraj::terrain
