#pragma once
// FourWheelAttitudeModel: a rigid chassis on four wheels (wheelbase L, track W) resting on the
// terrain.
//
// Contact rule: the chassis plane is the least-squares plane through the four contact heights
// h_i = g(x_i, y_i), sampled at the wheels' horizontal positions (x, y) + R(heading) (+-L/2,
// +-W/2). For a rectangle the fit is closed form: z = mean(h), forward slope
// p = (h_fl + h_fr - h_rl - h_rr) / (2 L), left slope q = (h_fl + h_rl - h_fr - h_rr) / (2 W);
// pitch and roll follow from (p, q) as for a plane (planeAttitude()). A rigid chassis cannot
// touch four arbitrary heights; the least-squares plane is the symmetric compromise and is
// smooth in the pose (the three-of-four support is not). Horizontal wheel offsets neglect the
// shortening of the footprint on a slope (a relative error of 1 - cos(pitch), 4.5 % at 17 deg).

#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::models {

/// Chassis dimensions [m].
struct FourWheelGeometry {
  double wheelbase = 0.5;  ///< front to rear axle, > 0
  double track = 0.4;      ///< left to right wheel, > 0
};

/// Attitude of a rigid four-wheel chassis.
class FourWheelAttitudeModel final : public TerrainFollowingModel {
 public:
  /// Throws std::invalid_argument for non-positive dimensions.
  FourWheelAttitudeModel(const terrain::TerrainSurface& surface, const FourWheelGeometry& geometry);

  AttitudeStatus compute(const PlanarPose& pose, AttitudeWorkspace& workspace,
                         AttitudeResult& result) const override;
  const char* name() const override { return "four_wheel"; }
  const terrain::TerrainSurface& surface() const override { return surface_; }
  /// Half the diagonal between the wheels [m].
  double samplingRadius() const override;
  const FourWheelGeometry& geometry() const { return geometry_; }

 private:
  terrain::TerrainSurface surface_;
  FourWheelGeometry geometry_;
};

}  // namespace terratraj::models
