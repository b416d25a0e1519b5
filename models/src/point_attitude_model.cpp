#include "terratraj/models/point_attitude_model.hpp"

#include <cmath>

namespace terratraj::models {

PlaneAttitude planeAttitude(double p, double q) {
  const double one_p2 = 1.0 + p * p;
  const double root = std::sqrt(one_p2);
  const double r = q / root;  // tan(roll)
  const double droll_dr = 1.0 / (1.0 + r * r);
  return {std::atan(p), std::atan(r), 1.0 / one_p2, droll_dr * (-q * p / (one_p2 * root)),
          droll_dr / root};
}

void setPlaneAttitude(double z, const Eigen::RowVector3d& dz, double p,
                      const Eigen::RowVector3d& dp, double q, const Eigen::RowVector3d& dq,
                      AttitudeResult& result) {
  const PlaneAttitude plane = planeAttitude(p, q);
  result.attitude = {z, plane.roll, plane.pitch};
  result.jacobian.row(0) = dz;
  result.jacobian.row(1) = plane.droll_dp * dp + plane.droll_dq * dq;
  result.jacobian.row(2) = plane.dpitch_dp * dp;
  result.suspension.setZero();
  result.contact_residual = 0.0;
  result.iterations = 0;
}

AttitudeStatus PointAttitudeModel::compute(const PlanarPose& pose, AttitudeWorkspace& /*workspace*/,
                                           AttitudeResult& result) const {
  const std::optional<terrain::SurfaceDerivatives> d =
      surface_.sampleWithHessian(Eigen::Vector2d(pose.x, pose.y));
  if (!d) return AttitudeStatus::kNoTerrain;
  const double c = std::cos(pose.heading);
  const double s = std::sin(pose.heading);
  const double gx = d->gradient.x(), gy = d->gradient.y();
  const double hxx = d->hessian(0, 0), hxy = d->hessian(0, 1), hyy = d->hessian(1, 1);
  // Slopes along the heading (p) and to the left (q), and their derivatives by (x, y, heading).
  const double p = gx * c + gy * s;
  const double q = -gx * s + gy * c;
  const Eigen::RowVector3d dp(hxx * c + hxy * s, hxy * c + hyy * s, q);
  const Eigen::RowVector3d dq(-hxx * s + hxy * c, -hxy * s + hyy * c, -p);
  setPlaneAttitude(d->height, Eigen::RowVector3d(gx, gy, 0.0), p, dp, q, dq, result);
  return AttitudeStatus::kOk;
}

}  // namespace terratraj::models
