#pragma once
// Local mesh refinement of a transcription from its verification: which intervals to halve.
//
// A transcription holds the ground's limits (pitch, roll, the speed tables, the Segway's slope
// bounds) at its points only; its re-simulation finds where they break between the points, and
// its local integration error (intervalErrors) where the re-simulated end drifts from the
// goal. Halving only those intervals keeps the re-solve near its start (the new points lie on
// ground the previous solution already drove) and its cost near the previous round's, where
// doubling every interval re-poses the whole problem: on a DEM at rover scale (davosdorf at
// 0.25 m cells, the Segway) a doubled round started 0.55 away from feasible at its new points
// and wandered 500 iterations (case 405 of `bench robustness --seed 11`).

#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::ocp {

/// How far one state breaks the ground's limits, relative: the largest of |pitch| / pitch_max
/// - 1, |roll| / roll_max - 1 and the speed `v` [m/s] over the problem's speed tables at
/// `attitude` and `curvature` [1/m] (SpeedTables::speedCap) relative to v_max; <= 0 when all
/// hold. What guessLimitExcess and intervalLimitExcess read at each of their samples.
double groundLimitExcess(const BoundaryValueProblem& problem, const models::Attitude& attitude,
                         double v, double curvature);

/// The largest relative excess of the ground's limits within each interval of `mesh_times`
/// (node times [s], increasing, from the trajectory's first time), read from the samples of a
/// re-simulated `trajectory` (their pitch and roll columns, the model's): |pitch| / pitch_max
/// - 1, |roll| / roll_max - 1, the speed over the problem's speed tables at that attitude
/// (SpeedTables::speedCap) relative to v_max, and the acceleration between two samples over
/// SpeedTables::accelerationCap (the wider of its two ends) relative to a_max; 0 where all hold.
/// One value per interval (mesh_times.size() - 1); samples past the last node count in the
/// last interval.
std::vector<double> intervalLimitExcess(const models::Trajectory& trajectory,
                                        const std::vector<double>& mesh_times,
                                        const BoundaryValueProblem& problem);

/// `mesh` (normalised node times, 0 to 1) with every interval whose `split` entry is true
/// halved, in order, while the mesh has fewer than `max_intervals` intervals.
std::vector<double> splitIntervals(const std::vector<double>& mesh, const std::vector<bool>& split,
                                   int max_intervals);

}  // namespace terratraj::ocp
