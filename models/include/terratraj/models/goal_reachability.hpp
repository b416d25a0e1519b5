#pragma once
// GoalReachability: whether a goal can be reached from a start at all, decided before any
// solver runs, so that a goal boxed in by slopes beyond the pitch and roll limits (or by lethal
// and no-data cells) is reported `infeasible` with the reason at once instead of after every
// seed has spent its iterations (issue 17, "Bad input and failure").
//
// The test is a relaxation of the real problem, so "unreachable" is a proof (up to the sampling
// below) and "reachable" is not a promise. A best-first search over states (cell, heading
// sector), `sectors` equal sectors of the circle, from the start's cell and heading towards the
// goal's cell and heading. A state is open when the cell is on the map, not lethal, not no-data,
// and the vehicle rests there with |pitch| and |roll| within (1 + limit_tolerance) x the limits
// (pitch_max, roll_max) at some sample: the cell's centre or a corner, at a heading of the
// sector (its middle, edges and quarter points). A forward-driving trajectory whose heading is
// continuous moves between open states only in two ways: it turns into the next sector inside
// a cell, or it crosses into a neighbouring cell with a heading that has a positive component
// across the shared edge (for a corner, across both edges). The search allows exactly those
// moves. It ignores speed, curvature, their rates, the speed tables and the map margin, each of
// which only removes trajectories; the tolerance covers the attitude between the samples. The
// start's and the goal's own states always count as open. A first, cheaper search by cell (a
// cell open when any of its sectors is, every neighbour enterable) settles a goal boxed in by
// lethal cells with one state per cell (a whole 559 x 495 map: 0.4 s for the point model, 4.8 s
// for the rocker-bogie, against 5 s and 42 s by sector); only when it reaches the goal does the
// search by sector run. When that reaches the goal too, the curvature check
// (curvature_trap.hpp) asks whether any path with the vehicle's turning radius can arrive at the
// goal's pose, then leave the start's: a goal on a side slope that the vehicle can only stand
// on at its own heading, between ridges it cannot cross, is proved unreachable there.

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/curvature_trap.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::models {

/// The curvature check's default sizes: boxes of 2 cm and 2 deg with moves of 0.15 m, then
/// the defaults of CurvatureTrapOptions (1 cm, 1 deg, 0.1 m).
std::vector<CurvatureTrapOptions> defaultCurvatureLevels();

/// How finely the flood fill samples a cell.
struct GoalReachabilityOptions {
  int sectors = 16;              ///< heading sectors, >= 4
  double limit_tolerance = 0.1;  ///< relative slack on pitch_max and roll_max, >= 0
  /// Wall clock the search may take [s]; when over, the check ends undecided (reachable, with
  /// `decided` false). Absent: none (a whole map at worst).
  std::optional<double> time_limit_s;
  /// The curvature check at both ends (curvature_trap.hpp), tried at these sizes in turn until
  /// one proves a trap; empty: not made. Boxes of 2 cm first (a dead end narrower than the
  /// turning circle: a region of 10^5 boxes), then of 1 cm (a pocket between thin ridges).
  std::vector<CurvatureTrapOptions> curvature = defaultCurvatureLevels();
};

/// The outcome of checkGoalReachability().
struct GoalReachability {
  bool reachable = true;
  bool decided = true;  ///< false: the time limit ended the search first (reachable is true)
  /// Why not (empty when reachable): the cells reached, their area and the limits that box the
  /// start in, as a sentence for a report.
  std::string reason;
  std::size_t states_visited = 0;    ///< states both searches took from their queues
  std::size_t cells_reached = 0;     ///< distinct cells the last search reached
  std::size_t attitude_samples = 0;  ///< vehicle attitudes computed
  double time_ms = 0.0;              ///< wall clock of the check [ms]
  /// The curvature checks made, after the search by sector reached the goal: at the goal
  /// (paths arriving), then, unless that one proved the goal unreachable, at the start.
  std::optional<CurvatureTrap> goal_trap, start_trap;
};

/// Whether `goal` can be reached from `start` [m, map-local, rad] by `vehicle` driving forwards
/// on `map` within `limits`' pitch_max and roll_max (see the file comment). Never throws
/// (except std::bad_alloc); start or goal off the map: reachable with nothing checked (the
/// problem's validation names that). Its cost is about one attitude per cell on the way when
/// the goal is reachable over open terrain, and every state of the start's region when it is
/// not (a whole map at worst: see time_limit_s).
GoalReachability checkGoalReachability(const TerrainFollowingModel& vehicle,
                                       const terrain::ElevationMap& map,
                                       const VehicleLimits& limits, const PlanarPose& start,
                                       const PlanarPose& goal,
                                       const GoalReachabilityOptions& options = {});

}  // namespace terratraj::models
