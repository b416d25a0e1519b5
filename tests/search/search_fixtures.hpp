#pragma once
// Small planning problems for the search tests: generated maps, the point vehicle, limits.

#include <memory>

#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::search::testing {

/// A map, the point vehicle on it and a problem from the standard start to the standard goal
/// (both heading east, at rest). Not copyable: the problem points into the fixture.
struct TestWorld {
  explicit TestWorld(terrain::ElevationMap map_in)
      : map(std::move(map_in)),
        surface(map, terrain::Interpolation::kBicubic),
        vehicle(surface),
        problem(map, vehicle) {
    const auto [start, goal] = terrain::standardStartGoal(map.geometry());
    problem.start.position = start;
    problem.goal.position = goal;
    problem.limits.pitch_max = problem.limits.roll_max = 0.45;
  }
  TestWorld(const TestWorld&) = delete;
  TestWorld& operator=(const TestWorld&) = delete;

  terrain::ElevationMap map;
  terrain::TerrainSurface surface;
  models::PointAttitudeModel vehicle;
  PlanningProblem problem;
};

/// A generated map of `kind`, rows x cols cells of 0.25 m.
inline terrain::ElevationMap generated(terrain::TerrainKind kind, int size, std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.kind = kind;
  options.rows = options.cols = size;
  options.cell = 0.25;
  options.seed = seed;
  return terrain::generateTerrain(options);
}

inline std::unique_ptr<TestWorld> makeWorld(terrain::TerrainKind kind, int size,
                                            std::uint64_t seed = 1) {
  return std::make_unique<TestWorld>(generated(kind, size, seed));
}

}  // namespace terratraj::search::testing
