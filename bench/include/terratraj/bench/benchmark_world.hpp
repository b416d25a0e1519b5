#pragma once
// BenchmarkWorld: what the planner benchmarks (bench/ and `terratraj bench`) share: generated
// maps of 0.25 m cells, the example problem's limits, and a vehicle on a map with start and
// goal placed on moderate ground.

#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {

inline constexpr double kBenchmarkCell = 0.25;  ///< [m]

/// The problem files' limits (examples/plan_problem.yaml); pitch_max [deg] is the
/// expansiveness knob of 001_... (a lower limit leaves fewer ways through).
models::VehicleLimits benchmarkLimits(double pitch_max_deg = 17.0);

/// The attitude models the benchmarks use.
enum class BenchmarkVehicle { kPoint, kRockerBogie };
/// "point" or "rocker_bogie".
const char* benchmarkVehicleName(BenchmarkVehicle vehicle);
/// The attitude model on `surface` (which must outlive it).
std::unique_ptr<models::TerrainFollowingModel> makeBenchmarkVehicle(
    BenchmarkVehicle vehicle, const terrain::TerrainSurface& surface);

/// A generated map of size x size cells of kBenchmarkCell.
terrain::ElevationMap generateBenchmarkMap(terrain::TerrainKind kind, int size, std::uint64_t seed);

/// A map, a vehicle on it and a planning problem. Not copyable: the problem points into it.
struct BenchmarkWorld {
  BenchmarkWorld(terrain::ElevationMap map_in, BenchmarkVehicle kind,
                 const models::VehicleLimits& limits);
  BenchmarkWorld(const BenchmarkWorld&) = delete;
  BenchmarkWorld& operator=(const BenchmarkWorld&) = delete;

  /// Whether the vehicle rests at `p` (heading east) within half its pitch and roll limits:
  /// start and goal are put on moderate ground, not on the edge of what the vehicle can climb.
  bool moderate(const Eigen::Vector2d& p) const;
  /// Puts start and goal at the given points (at rest, heading east), each moved north 0.5 m
  /// at a time (up to 200 times) until it is valid and on moderate ground. False when either
  /// found no such place.
  bool place(const Eigen::Vector2d& start, const Eigen::Vector2d& goal);
  /// Start-goal distance [m].
  double distance() const;
  /// The bang-bang time along the straight line from start to goal at rest [s]: a lower bound
  /// of any trajectory's duration.
  double lowerBoundTime() const;

  terrain::ElevationMap map;
  terrain::TerrainSurface surface;
  std::unique_ptr<models::TerrainFollowingModel> vehicle;
  search::PlanningProblem problem;
  bool placed = false;
};

}  // namespace terratraj::bench
