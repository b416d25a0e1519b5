#pragma once
// The boundary-value problem sets of 004_... used by the tests, the benchmarks and
// `terratraj bench convergence`: the flat 45-goal fan (fig. 5), the 35-node / 94-edge lattice
// on rough terrain (fig. 4), the single hill of the slope-dwell experiment (figs. 6-7), and
// seeded random problems on a real elevation model.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/raster_io.hpp"

namespace terratraj::bench::problem_sets {

using ocp::BoundaryValueProblem;

/// Whether every cell within `margin` [m] of (x, y) [m, local frame] is on the map, holds data
/// and is not lethal (problem ends a vehicle can stand on, away from the edges).
bool clearAround(const terrain::ElevationMap& map, double x, double y, double margin);

/// Limits loose enough that the unconstrained parametric solvers are judged on convergence.
models::VehicleLimits looseLimits();

/// A constant-speed (v = 0.5 m/s) minimum-time problem with looseLimits() [m, rad].
BoundaryValueProblem cruise(double x0, double y0, double h0, double x1, double y1, double h1);

/// Flat ground, 20 m x 20 m at 0.25 m.
terrain::ElevationMap flatMap();
/// 004_... fig. 5: from (3, 10, 0), goals 5 m away at bearings -40..40 deg (9) and headings
/// -60..60 deg (5): 45 problems on flatMap().
std::vector<BoundaryValueProblem> flatFan();

/// Rough terrain for the lattice: generated hills (seed 7), 16 m x 12 m at 0.25 m.
terrain::ElevationMap roughMap();
/// 004_... fig. 4: 35 nodes (7 columns 2 m apart x 5 rows 0.75 m apart, heading 0) and 94
/// edges drawn with seed 4 from the 114 forward edges (next column, row change <= 2).
std::vector<BoundaryValueProblem> roughLattice();

/// 004_... figs. 6-7: flat ground with one hill (height 0.6 m, sigma 0.7 m) centred 0.35 m left
/// of the line from (2, 5) to the goal 4 m ahead.
terrain::ElevationMap singleHillMap();
/// The slope-dwell problem on singleHillMap(): relative goal (4, 0, 0) at constant speed;
/// alpha = 0 is minimum time.
BoundaryValueProblem singleHillProblem(double alpha);

/// How random problems are drawn on an elevation model.
struct RandomProblemOptions {
  int count = 20;               ///< problems, >= 1
  std::uint64_t seed = 1;       ///< same seed, same problems
  double min_distance_m = 3.0;  ///< start-goal distance range [m]
  double max_distance_m = 6.0;
  double max_heading_change =
      1.0;                     ///< |goal heading - bearing| and |start heading - bearing| [rad]
  double edge_margin_m = 2.0;  ///< start and goal at least this far inside the data [m]
};

/// `count` cruise problems on `map` with start and goal on cells holding data (and their
/// neighbours within the margin). Throws InputError when the map has no room for them (too
/// small, or too few data cells after 100 x count draws).
std::vector<BoundaryValueProblem> randomProblems(const terrain::ElevationMap& map,
                                                 const RandomProblemOptions& options);

}  // namespace terratraj::bench::problem_sets
