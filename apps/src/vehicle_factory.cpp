#include "terratraj/apps/vehicle_factory.hpp"

#include "terratraj/models/four_wheel_attitude_model.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"

namespace terratraj::apps {

std::unique_ptr<models::TerrainFollowingModel> makeTerrainFollowingModel(
    VehicleModelKind kind, const terrain::TerrainSurface& surface) {
  switch (kind) {
    case VehicleModelKind::kFourWheel:
      return std::make_unique<models::FourWheelAttitudeModel>(surface, models::FourWheelGeometry{});
    case VehicleModelKind::kRockerBogie:
      return std::make_unique<models::RockerBogieAttitudeModel>(surface);
    case VehicleModelKind::kPoint:
    case VehicleModelKind::kSegwayRmp:
      break;
  }
  return std::make_unique<models::PointAttitudeModel>(surface);
}

}  // namespace terratraj::apps
