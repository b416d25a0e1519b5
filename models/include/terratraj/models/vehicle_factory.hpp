#pragma once
// VehicleModelKind and makeTerrainFollowingModel: the vehicle models by name, as a problem file's
// `vehicle.model` names them, built with their default geometry.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::models {

/// Vehicle models, named point | four_wheel | rocker_bogie | segway_rmp.
enum class VehicleModelKind { kPoint, kFourWheel, kRockerBogie, kSegwayRmp };

/// The name of a vehicle model ("point", ...).
const char* vehicleModelName(VehicleModelKind kind);
/// Parses a vehicle model name; std::nullopt if it is not one.
std::optional<VehicleModelKind> parseVehicleModelKind(std::string_view name);
/// Every vehicle model name, in declaration order.
std::vector<std::string> vehicleModelNames();

/// The terrain-following model of a vehicle kind, with default geometry: point, four_wheel,
/// rocker_bogie; segway_rmp rests like a point (001_...: the RMP is planned as a point; its
/// dynamics are the transcription's SegwayConstraints). The surface must outlive the model.
std::unique_ptr<TerrainFollowingModel> makeTerrainFollowingModel(
    VehicleModelKind kind, const terrain::TerrainSurface& surface);

}  // namespace terratraj::models
