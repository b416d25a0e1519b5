#pragma once
// The Segway's test problem of the transcription tests: rest to rest along +x, its paper's limits.

#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::ocp::testing {

/// Rest to rest from (4, 5) to (goal_x, 5) [m], heading 0, with v_max 3.5 m/s, a_max 2 m/s^2,
/// `pitch_max` [rad] and `lookups` (which must outlive the problem).
inline BoundaryValueProblem segwayAlongX(const models::SegwayLookups& lookups, double goal_x,
                                         double pitch_max) {
  BoundaryValueProblem problem;
  problem.start = {4.0, 5.0, 0.0, 0.0, 0.0};
  problem.goal = {goal_x, 5.0, 0.0, 0.0, 0.0};
  problem.limits.v_max = 3.5;
  problem.limits.a_max = 2.0;
  problem.limits.pitch_max = pitch_max;
  problem.tables.segway = &lookups;
  return problem;
}

}  // namespace terratraj::ocp::testing
