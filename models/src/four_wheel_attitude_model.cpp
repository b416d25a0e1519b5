#include "terratraj/models/four_wheel_attitude_model.hpp"

#include <cmath>
#include <stdexcept>

#include "terratraj/models/point_attitude_model.hpp"

namespace terratraj::models {

FourWheelAttitudeModel::FourWheelAttitudeModel(const terrain::TerrainSurface& surface,
                                               const FourWheelGeometry& geometry)
    : surface_(surface), geometry_(geometry) {
  if (!(geometry.wheelbase > 0.0) || !(geometry.track > 0.0)) {
    throw std::invalid_argument("four_wheel: wheelbase and track must be > 0");
  }
}

double FourWheelAttitudeModel::samplingRadius() const {
  return 0.5 * std::hypot(geometry_.wheelbase, geometry_.track);
}

AttitudeStatus FourWheelAttitudeModel::compute(const PlanarPose& pose,
                                               AttitudeWorkspace& /*workspace*/,
                                               AttitudeResult& result) const {
  const double c = std::cos(pose.heading);
  const double s = std::sin(pose.heading);
  const double half_l = 0.5 * geometry_.wheelbase;
  const double half_w = 0.5 * geometry_.track;
  // Wheels: front-left, front-right, rear-left, rear-right (forward u, left w offsets), and
  // the weights of their heights in z (mean), p (forward slope) and q (left slope).
  constexpr double kU[4] = {1, 1, -1, -1};
  constexpr double kW[4] = {1, -1, 1, -1};
  double z = 0.0, p = 0.0, q = 0.0;
  Eigen::RowVector3d dz = Eigen::RowVector3d::Zero(), dp = dz, dq = dz;
  for (int i = 0; i < 4; ++i) {
    const double u = kU[i] * half_l;
    const double w = kW[i] * half_w;
    const Eigen::Vector2d at(pose.x + u * c - w * s, pose.y + u * s + w * c);
    const std::optional<terrain::HeightSample> h = surface_.sample(at);
    if (!h) return AttitudeStatus::kNoTerrain;
    const Eigen::RowVector3d dh(h->gradient.x(), h->gradient.y(),
                                h->gradient.dot(Eigen::Vector2d(-u * s - w * c, u * c - w * s)));
    const double wz = 0.25, wp = kU[i] / (4.0 * half_l), wq = kW[i] / (4.0 * half_w);
    z += wz * h->height;
    p += wp * h->height;
    q += wq * h->height;
    dz += wz * dh;
    dp += wp * dh;
    dq += wq * dh;
  }
  setPlaneAttitude(z, dz, p, dp, q, dq, result);
  return AttitudeStatus::kOk;
}

}  // namespace terratraj::models
