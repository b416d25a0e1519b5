#pragma once
// ProblemScene: what `check`, `solve` and `plan` load for a problem file before they differ:
// its terrain, the surface and vehicle model on it, and the look-up tables it names, with the
// start and goal resolved on the map and checked to be places the vehicle can rest.

#include <memory>
#include <optional>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::apps {

/// A problem's terrain, vehicle and tables. Not copyable or movable: the surface and the model
/// point into the map.
class ProblemScene {
 public:
  /// Loads the terrain of `problem` and resolves its start and goal on the map (start(),
  /// goal(); `problem` is not changed), reads its tables, builds the bicubic surface and the
  /// vehicle model, and computes the vehicle's resting attitude at start and goal. Throws
  /// InputError naming the file / key / value at fault (unreadable terrain or table, pose off
  /// the map or where the vehicle cannot rest).
  ProblemScene(const ProblemSpec& problem, const CommandContext& context);
  ProblemScene(const ProblemScene&) = delete;
  ProblemScene& operator=(const ProblemScene&) = delete;

  const terrain::ElevationMap& map() const { return map_; }
  /// The start and goal in the local map frame (converted from the world frame when the file
  /// gives them so).
  const BoundaryState& start() const { return poses_.start; }
  const BoundaryState& goal() const { return poses_.goal; }
  const terrain::TerrainSurface& surface() const { return surface_; }
  const models::TerrainFollowingModel& vehicle() const { return *vehicle_; }
  /// The tables the problem names, or null.
  const models::PitchSpeedTable* pitchTable() const {
    return pitch_table_ ? &*pitch_table_ : nullptr;
  }
  const models::RollCurvatureSpeedTable* rollCurvatureTable() const {
    return roll_table_ ? &*roll_table_ : nullptr;
  }
  /// The Segway RMP's look-ups (models::defaultSegwayLookups()) for that vehicle, else null.
  const models::SegwayLookups* segwayLookups() const {
    return segway_lookups_ ? &*segway_lookups_ : nullptr;
  }
  /// The Segway RMP's pitch response for the CSVs' platform_pitch column, else null.
  const models::SegwayPitchResponse* platformPitchResponse() const {
    return segway_lookups_ ? &segway_lookups_->pitch_response : nullptr;
  }
  /// The speed limit by pitch the searches hold: the Segway's speed bound by slope
  /// (models::slopeSpeedTable, with the problem's pitch table when it names one) for that
  /// vehicle, else pitchTable().
  const models::PitchSpeedTable* searchPitchTable() const {
    return search_pitch_table_ ? &*search_pitch_table_ : pitchTable();
  }
  /// The vehicle at rest at the start and at the goal.
  const models::AttitudeResult& startAttitude() const { return start_attitude_; }
  const models::AttitudeResult& goalAttitude() const { return goal_attitude_; }

 private:
  terrain::ElevationMap map_;
  ResolvedPoses poses_;
  std::optional<models::PitchSpeedTable> pitch_table_;
  std::optional<models::RollCurvatureSpeedTable> roll_table_;
  std::optional<models::SegwayLookups> segway_lookups_;
  std::optional<models::PitchSpeedTable> search_pitch_table_;
  terrain::TerrainSurface surface_;
  std::unique_ptr<models::TerrainFollowingModel> vehicle_;
  models::AttitudeResult start_attitude_, goal_attitude_;
};

}  // namespace terratraj::apps
