#pragma once
// Building the models a problem's `vehicle` section names.

#include <memory>

#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::apps {

/// The terrain-following model of a vehicle kind, with default geometry: point, four_wheel,
/// rocker_bogie; segway_rmp rests like a point (001_...: the RMP is planned as a point). The
/// surface must outlive the model.
std::unique_ptr<models::TerrainFollowingModel> makeTerrainFollowingModel(
    VehicleModelKind kind, const terrain::TerrainSurface& surface);

}  // namespace terratraj::apps
