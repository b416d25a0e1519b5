#include "terratraj/ocp/flat_ground_model.hpp"

namespace terratraj::ocp {

models::AttitudeStatus FlatGroundModel::compute(const models::PlanarPose& /*pose*/,
                                                models::AttitudeWorkspace& /*workspace*/,
                                                models::AttitudeResult& result) const {
  result = models::AttitudeResult{};
  return models::AttitudeStatus::kOk;
}

}  // namespace terratraj::ocp
