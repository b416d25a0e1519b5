#pragma once
// TerrainFollowingModel: how a vehicle sits on the terrain. Given a planar pose it computes the
// height of the vehicle's reference point, roll, pitch, their derivatives with respect to the
// pose, and (for articulated suspensions) the suspension configuration.
//
// Problem vs workspace (as in Crocoddyl): a model is immutable and may be shared; everything a
// computation writes lives in an AttitudeWorkspace owned by the caller (one per thread), which
// also carries the warm start of iterative models. No allocation happens in compute().

#include <Eigen/Core>
#include <memory>
#include <string_view>

#include "terratraj/models/attitude.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::models {

/// Scratch space and warm start of one caller. Cheap to create; reuse it along a trajectory.
struct AttitudeWorkspace {
  /// Last solution of an iterative model: (z, roll, pitch, rho, beta1, beta2).
  Eigen::Matrix<double, 6, 1> warm_start = Eigen::Matrix<double, 6, 1>::Zero();
  /// Whether warm_start holds a solution (set by models, cleared by the caller to force a
  /// cold start).
  bool has_warm_start = false;
};

/// The terrain-following models the problem file names (`vehicle.model`).
enum class TerrainFollowingKind { kPoint, kFourWheel, kRockerBogie };

/// A vehicle resting on a terrain surface.
class TerrainFollowingModel {
 public:
  virtual ~TerrainFollowingModel() = default;

  /// Attitude at `pose` [m, rad]. Writes `result` and updates `workspace`; never throws and
  /// never allocates. On a status other than kOk, `result` is unspecified.
  virtual AttitudeStatus compute(const PlanarPose& pose, AttitudeWorkspace& workspace,
                                 AttitudeResult& result) const = 0;
  /// The model's name ("point", "four_wheel", "rocker_bogie").
  virtual const char* name() const = 0;
  /// The surface the model rests on.
  virtual const terrain::TerrainSurface& surface() const = 0;
  /// An upper bound [m] on the planar distance from the reference point (pose.x, pose.y) to
  /// every point where compute() samples the surface, for any heading, attitude and suspension
  /// configuration: where the surface is undefined within it, compute() may fail.
  virtual double samplingRadius() const = 0;
};

}  // namespace terratraj::models
