#pragma once
// PlanningProblem: what a planner is asked (OMPL's problem definition): the terrain, the
// vehicle (attitude model, limits, optional kinodynamic tables), the start state and the goal
// region. Planners only read it; it holds references, so the map, model and tables must
// outlive it.

#include <optional>
#include <string>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/search/goal_region.hpp"
#include "terratraj/search/planner_state.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::search {

/// One planning query.
struct PlanningProblem {
  /// The problem on `map` for a vehicle resting by `vehicle` (whose surface must be a view of
  /// the same map).
  PlanningProblem(const terrain::ElevationMap& map_, const models::TerrainFollowingModel& vehicle_)
      : map(&map_), vehicle(&vehicle_) {}

  const terrain::ElevationMap* map;                      ///< heights, lethal layer
  const models::TerrainFollowingModel* vehicle;          ///< attitude (z, roll, pitch) at a pose
  models::VehicleLimits limits;                          ///< constraints (1), (3)-(6)
  const models::PitchSpeedTable* pitch_table = nullptr;  ///< optional: v_max by pitch
  const models::RollCurvatureSpeedTable* roll_curvature_table = nullptr;  ///< optional
  PlannerState start;                                                     ///< where the plan starts
  GoalRegion goal;                                                        ///< where it may end

  /// Checks the problem before planning. Returns a message naming the field at fault
  /// ("start", "goal", "limits.v_max", ...) or std::nullopt when it is valid:
  /// limits and tolerances > 0; start and goal on the map, on cells neither lethal nor no
  /// data, with an attitude the vehicle can rest in and within pitch_max / roll_max; speeds in
  /// [0, v_max]; the start's |curvature| <= kappa_max and |omega| <= omega_max.
  std::optional<std::string> validate() const;
};

}  // namespace terratraj::search
