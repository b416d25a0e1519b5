#pragma once
// FlatGroundModel: a vehicle on a horizontal plane (roll = pitch = 0, z = 0) wherever it is:
// the flat-ground problem of 004_... 3.5 that seeds the terrain-adaptive solve.

#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::ocp {

/// Zero attitude everywhere; never fails. `surface()` returns the surface it was built with
/// (never sampled), so the model can stand in for the real one.
class FlatGroundModel final : public models::TerrainFollowingModel {
 public:
  /// The surface must outlive the model.
  explicit FlatGroundModel(const terrain::TerrainSurface& surface) : surface_(&surface) {}
  models::AttitudeStatus compute(const models::PlanarPose& pose,
                                 models::AttitudeWorkspace& workspace,
                                 models::AttitudeResult& result) const override;
  const char* name() const override { return "flat"; }
  const terrain::TerrainSurface& surface() const override { return *surface_; }
  double samplingRadius() const override { return 0.0; }  ///< never samples

 private:
  const terrain::TerrainSurface* surface_;
};

}  // namespace terratraj::ocp
