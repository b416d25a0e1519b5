#pragma once
// PointAttitudeModel: a point vehicle whose attitude is that of the terrain's tangent plane under
// it (001_... III.B): z = g(x, y), pitch = atan(p), roll = atan(q / sqrt(1 + p^2)), where p and q
// are the surface's slopes along the heading and to the left. Closed form, analytic Jacobian
// from the surface's Hessian.

#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::models {

/// Attitude from the terrain normal under a point.
class PointAttitudeModel final : public TerrainFollowingModel {
 public:
  explicit PointAttitudeModel(const terrain::TerrainSurface& surface) : surface_(surface) {}

  AttitudeStatus compute(const PlanarPose& pose, AttitudeWorkspace& workspace,
                         AttitudeResult& result) const override;
  const char* name() const override { return "point"; }
  const terrain::TerrainSurface& surface() const override { return surface_; }
  double samplingRadius() const override { return 0.0; }  ///< the point itself

 private:
  terrain::TerrainSurface surface_;
};

/// Pitch and roll of a plane with slope p along the heading and q to the left (both dz per
/// horizontal metre), with their derivatives: {pitch, roll, dpitch/dp, droll/dp, droll/dq}.
struct PlaneAttitude {
  double pitch, roll, dpitch_dp, droll_dp, droll_dq;
};
PlaneAttitude planeAttitude(double p, double q);

/// Fills `result` for a rigid vehicle on a plane of height z and slopes (p, q), given their
/// derivatives by (x, y, heading); no suspension, no iterations.
void setPlaneAttitude(double z, const Eigen::RowVector3d& dz, double p,
                      const Eigen::RowVector3d& dp, double q, const Eigen::RowVector3d& dq,
                      AttitudeResult& result);

}  // namespace terratraj::models
