#pragma once
// Whether the start and the goal themselves hold the speed look-ups (internal to refine/src):
// a trajectory's first and last rows are its ends, so an end the look-ups forbid is a goal no
// trajectory can reach, whatever the route.

#include <optional>

#include "terratraj/models/goal_reachability.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::refine::detail {

/// The goal proved unreachable by an end state (with the reason, naming the end, its slope and
/// the bound), or std::nullopt:
///  - the Segway at rest or moving where its look-ups allow no speed or no acceleration (001_...
///    III.C): it can neither leave the start nor stop at the goal;
///  - an end's speed above the tables' bound at its attitude and curvature (`omega / v`:
///    ocp::SpeedTables::speedCap), by more than 1 % and the verdict's slack (1e-3 relative,
///    1e-6 m/s): the verdict checks that bound at the first and the last rows, which are the
///    ends within the solver's tolerance (1 mm, 1e-3 rad), hence the margin.
/// An end where the vehicle cannot rest is left to the problem's validation. Never throws
/// (except std::bad_alloc).
std::optional<models::GoalReachability> checkEndStates(const models::TerrainFollowingModel& vehicle,
                                                       const ocp::BoundaryValueProblem& problem);

}  // namespace terratraj::refine::detail
