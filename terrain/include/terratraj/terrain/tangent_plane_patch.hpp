#pragma once
// TangentPlanePatch: the local planar patch under a vehicle, after Kobilarov & Sukhatme
// (001_..., III.B): over a short distance delta_g the vehicle moves on the plane tangent to the
// terrain at O, with frame F = (O, T, N x T, N).
//
// T is the unit tangent of the surface along the heading (its horizontal projection points
// along the heading), N the upward unit normal, B = N x T points to the vehicle's left. The
// rotation R = [T B N] (columns, in map coordinates) equals Rz(heading) Ry(-pitch) Rx(roll):
// pitch > 0 nose up, roll > 0 left side higher (docs/conventions.md).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::terrain {

/// A pose in a patch's own 2-D coordinates: (u, w) along (T, B) [m], angle from T toward B [rad].
struct PatchPose {
  double u = 0.0;
  double w = 0.0;
  double angle = 0.0;
};

/// The tangent plane of the terrain at a point, oriented along a heading.
class TangentPlanePatch {
 public:
  /// The patch at local map point `xy` [m] for map heading `heading` [rad] (0 = +x, CCW).
  /// std::nullopt where the surface has no value (off the map, near no data).
  static std::optional<TangentPlanePatch> at(const TerrainSurface& surface,
                                             const Eigen::Vector2d& xy, double heading);
  /// The patch through `origin` [m] with the given upward unit normal, for a heading [rad].
  /// Precondition: normal.z() > 0 (a surface z = g(x, y) never has a vertical tangent plane).
  static TangentPlanePatch fromNormal(const Eigen::Vector3d& origin, const Eigen::Vector3d& normal,
                                      double heading);

  /// O: the point of the surface where the patch starts [m, map frame].
  const Eigen::Vector3d& origin() const { return origin_; }
  /// R = [T B N]: patch axes as columns in map coordinates.
  const Eigen::Matrix3d& rotation() const { return rotation_; }
  Eigen::Vector3d tangent() const { return rotation_.col(0); }
  Eigen::Vector3d lateral() const { return rotation_.col(1); }
  Eigen::Vector3d normal() const { return rotation_.col(2); }
  /// Pitch of the patch along the heading [rad], > 0 when T climbs.
  double pitch() const;
  /// Roll of the patch about T [rad], > 0 when the left side (B) is higher.
  double roll() const;
  /// Map heading [rad] of T's horizontal projection.
  double heading() const;

  /// Map point [m] of a patch point (u, w) [m].
  Eigen::Vector3d toMap(double u, double w) const;
  /// Map heading [rad] of the horizontal projection of a direction at `angle` from T toward B.
  double mapHeadingOf(double angle) const;
  /// Rigid transform taking coordinates in this patch's frame to coordinates in `next`'s.
  Eigen::Isometry3d transformTo(const TangentPlanePatch& next) const;
  /// The patch a vehicle enters after moving to `pose_end` (in this patch's coordinates): its
  /// origin is the surface point under the end position and its heading the map heading of the
  /// direction of motion, so speed carries over continuously (001_..., III.B).
  /// std::nullopt where the surface has no value.
  std::optional<TangentPlanePatch> next(const TerrainSurface& surface,
                                        const PatchPose& pose_end) const;

 private:
  TangentPlanePatch(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation)
      : origin_(origin), rotation_(rotation) {}

  Eigen::Vector3d origin_;
  Eigen::Matrix3d rotation_;
};

}  // namespace terratraj::terrain
