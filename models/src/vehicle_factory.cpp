#include "terratraj/models/vehicle_factory.hpp"

#include <array>
#include <utility>

#include "terratraj/models/four_wheel_attitude_model.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"

namespace terratraj::models {
namespace {

constexpr std::array<std::pair<VehicleModelKind, const char*>, 4> kNames{{
    {VehicleModelKind::kPoint, "point"},
    {VehicleModelKind::kFourWheel, "four_wheel"},
    {VehicleModelKind::kRockerBogie, "rocker_bogie"},
    {VehicleModelKind::kSegwayRmp, "segway_rmp"},
}};

}  // namespace

const char* vehicleModelName(VehicleModelKind kind) {
  for (const auto& [value, name] : kNames) {
    if (value == kind) return name;
  }
  return "unknown";
}

std::optional<VehicleModelKind> parseVehicleModelKind(std::string_view name) {
  for (const auto& [value, text] : kNames) {
    if (name == text) return value;
  }
  return std::nullopt;
}

std::vector<std::string> vehicleModelNames() {
  std::vector<std::string> names;
  for (const auto& entry : kNames) names.emplace_back(entry.second);
  return names;
}

std::unique_ptr<TerrainFollowingModel> makeTerrainFollowingModel(
    VehicleModelKind kind, const terrain::TerrainSurface& surface) {
  switch (kind) {
    case VehicleModelKind::kFourWheel:
      return std::make_unique<FourWheelAttitudeModel>(surface, FourWheelGeometry{});
    case VehicleModelKind::kRockerBogie:
      return std::make_unique<RockerBogieAttitudeModel>(surface);
    case VehicleModelKind::kPoint:
    case VehicleModelKind::kSegwayRmp:
      break;
  }
  return std::make_unique<PointAttitudeModel>(surface);
}

}  // namespace terratraj::models
