#pragma once
// The robustness set of the optimal-control core (`terratraj bench convergence`, sets
// turns / turn_backs / <dem>_<vehicle>; the tests draw a few with other seeds): ordinary problems a
// user expects to be solved, where a local heuristic fails. Seeded: same seed, same problems.

#include <cstdint>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::bench::problem_sets {

using ocp::BoundaryValueProblem;

/// A rover's limits: v_max 1 m/s, a_max 0.5 m/s^2, omega_max 1 rad/s, kappa_max 1 1/m,
/// sigma_max 20 1/(m s) (a curvature change takes 5 cm at 1 m/s: the turns are nearly Dubins'),
/// pitch and roll 25 deg.
models::VehicleLimits roverLimits();

/// Flat ground, 30 m x 30 m at 0.25 m.
terrain::ElevationMap openFlatMap();

/// Curvature-limited turns at constant speed 1 m/s on openFlatMap() (roverLimits(): the speed
/// cannot rise, so the minimum time is the Dubins length over 1 m/s, up to the short clothoids
/// of sigma_max): from (15, 15, 0), goals 2 to 10 m away at any bearing, with any heading.
std::vector<BoundaryValueProblem> constantSpeedTurns(int count, std::uint64_t seed);

/// Rest-to-rest turn-backs on openFlatMap(): goals 2 to 5 m behind the start (bearing within
/// 45 deg of straight back), heading within 60 deg of pointing back.
std::vector<BoundaryValueProblem> turnBacks(int count, std::uint64_t seed);

/// Problems on a terrain for a vehicle: start and goal 4 to 12 m apart, each on a cell whose
/// neighbourhood within 1.5 m holds data and no lethal cell, where `vehicle` rests within the
/// pitch and roll of `limits`; even-numbered problems rest to rest, odd ones moving at
/// 0.5 v_max. Fewer than `count` when the map has no room (after 200 x count draws).
std::vector<BoundaryValueProblem> terrainProblems(const terrain::ElevationMap& map,
                                                  const models::TerrainFollowingModel& vehicle,
                                                  const models::VehicleLimits& limits, int count,
                                                  std::uint64_t seed);

}  // namespace terratraj::bench::problem_sets
