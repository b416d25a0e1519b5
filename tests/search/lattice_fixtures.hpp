#pragma once
// Shared pieces of the lattice tests: the default primitive set (generated once per process)
// and small hand-made maps.

#include <algorithm>
#include <memory>

#include "search_fixtures.hpp"
#include "terratraj/search/primitive_generator.hpp"

namespace terratraj::search::testing {

/// The default lattice (0.5 m, 16 headings) for the default limits, generated once.
inline const PrimitiveSet& defaultPrimitives() {
  static const PrimitiveSet set = generatePrimitives(LatticeSpec{}, models::VehicleLimits{}).set;
  return set;
}

/// A flat map of rows x cols cells of 0.25 m with a lethal layer (all free).
inline terrain::ElevationMap flatMap(int rows, int cols) {
  terrain::GridGeometry g;
  g.rows = rows;
  g.cols = cols;
  g.cell = 0.25;
  terrain::ElevationMap map(g);
  map.addLayer(terrain::layer_names::kLethal, 0.0f);
  return map;
}

/// Marks the cells of [x0, x1] x [y0, y1] (metres) lethal.
inline void block(terrain::ElevationMap& map, double x0, double y0, double x1, double y1) {
  terrain::GridLayer& lethal = *map.findLayer(terrain::layer_names::kLethal);
  const double cell = map.geometry().cell;
  const terrain::GridGeometry& g = map.geometry();
  for (int r = static_cast<int>(y0 / cell); r < std::min(g.rows, static_cast<int>(y1 / cell));
       ++r) {
    for (int c = static_cast<int>(x0 / cell); c < std::min(g.cols, static_cast<int>(x1 / cell));
         ++c) {
      lethal(r, c) = 1.0f;
    }
  }
}

/// A world on `map` from `start` to `goal` (heading east, at rest), default limits with pitch
/// and roll up to 0.45 rad.
inline std::unique_ptr<TestWorld> worldOn(terrain::ElevationMap map, const Eigen::Vector2d& start,
                                          const Eigen::Vector2d& goal) {
  auto world = std::make_unique<TestWorld>(std::move(map));
  world->problem.start.position = start;
  world->problem.goal.position = goal;
  return world;
}

}  // namespace terratraj::search::testing
