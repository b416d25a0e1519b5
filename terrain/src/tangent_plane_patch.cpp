#include "terratraj/terrain/tangent_plane_patch.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::terrain {

std::optional<TangentPlanePatch> TangentPlanePatch::at(const TerrainSurface& surface,
                                                       const Eigen::Vector2d& xy, double heading) {
  const std::optional<HeightSample> s = surface.sample(xy);
  if (!s) return std::nullopt;
  return fromNormal(Eigen::Vector3d(xy.x(), xy.y(), s->height), s->normal(), heading);
}

TangentPlanePatch TangentPlanePatch::fromNormal(const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& normal, double heading) {
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  // The surface direction whose horizontal projection is the heading: N . T = 0.
  const Eigen::Vector3d tangent =
      Eigen::Vector3d(c, s, -(normal.x() * c + normal.y() * s) / normal.z()).normalized();
  Eigen::Matrix3d rotation;
  rotation.col(0) = tangent;
  rotation.col(1) = normal.cross(tangent);
  rotation.col(2) = normal;
  return TangentPlanePatch(origin, rotation);
}

double TangentPlanePatch::pitch() const {
  return std::asin(std::clamp(rotation_(2, 0), -1.0, 1.0));
}

double TangentPlanePatch::roll() const { return std::atan2(rotation_(2, 1), rotation_(2, 2)); }

double TangentPlanePatch::heading() const { return std::atan2(rotation_(1, 0), rotation_(0, 0)); }

Eigen::Vector3d TangentPlanePatch::toMap(double u, double w) const {
  return origin_ + u * rotation_.col(0) + w * rotation_.col(1);
}

double TangentPlanePatch::mapHeadingOf(double angle) const {
  const Eigen::Vector3d direction =
      std::cos(angle) * rotation_.col(0) + std::sin(angle) * rotation_.col(1);
  return std::atan2(direction.y(), direction.x());
}

Eigen::Isometry3d TangentPlanePatch::transformTo(const TangentPlanePatch& next) const {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = next.rotation_.transpose() * rotation_;
  transform.translation() = next.rotation_.transpose() * (origin_ - next.origin_);
  return transform;
}

std::optional<TangentPlanePatch> TangentPlanePatch::next(const TerrainSurface& surface,
                                                         const PatchPose& pose_end) const {
  const Eigen::Vector3d end = toMap(pose_end.u, pose_end.w);
  return at(surface, end.head<2>(), mapHeadingOf(pose_end.angle));
}

}  // namespace terratraj::terrain
