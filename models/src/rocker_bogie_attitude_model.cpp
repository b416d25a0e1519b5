#include "terratraj/models/rocker_bogie_attitude_model.hpp"

#include <Eigen/LU>
#include <algorithm>

#include <cmath>
#include <stdexcept>

#include "terratraj/models/point_attitude_model.hpp"

namespace terratraj::models {
namespace {

using Vector6 = RockerBogieAttitudeModel::Vector6;
using Matrix6 = RockerBogieAttitudeModel::Matrix6;
using Matrix63 = RockerBogieAttitudeModel::Matrix63;

constexpr int kWheels = 6;
constexpr double kMaxAngleStep = 0.3;   // [rad] Newton step limit on any angle
constexpr double kMaxHeightStep = 0.2;  // [m] Newton step limit on z

// A rotation by `angle` about the body's lateral (y) axis, acting on (forward, up) vectors:
// positive angles turn forward toward down, as a right-handed rotation about +y does.
Eigen::Vector2d rotate(double angle, const Eigen::Vector2d& v) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {v.x() * c + v.y() * s, -v.x() * s + v.y() * c};
}

Eigen::Vector2d rotateDerivative(double angle, const Eigen::Vector2d& v) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {-v.x() * s + v.y() * c, -v.x() * c - v.y() * s};
}

Eigen::Vector3d toBody(const Eigen::Vector2d& in_plane, double lateral) {
  return {in_plane.x(), lateral, in_plane.y()};
}

// One wheel's centre in the body frame with its derivatives by rho and by its side's beta.
struct WheelInBody {
  Eigen::Vector3d position, d_rho, d_beta;
  int beta_index;  // 4 (beta1, left) or 5 (beta2, right)
};

// The six wheels: left rear, middle, front; right rear, middle, front.
void wheelsInBody(const RockerBogieGeometry& g, double rho, double beta1, double beta2,
                  WheelInBody (&wheels)[kWheels]) {
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? 1.0 : -1.0;  // left rocker turns by +rho, right by -rho
    const double lateral = sign * g.half_track;
    const double rocker = sign * rho;
    const double bogie = rocker + (side == 0 ? beta1 : beta2);
    const int beta_index = side == 0 ? 4 : 5;
    const Eigen::Vector2d pivot = rotate(rocker, g.bogie_pivot);
    const Eigen::Vector2d d_pivot = sign * rotateDerivative(rocker, g.bogie_pivot);
    WheelInBody* w = wheels + 3 * side;
    w[0] = {toBody(rotate(rocker, g.rear_wheel), lateral),
            toBody(sign * rotateDerivative(rocker, g.rear_wheel), 0.0), Eigen::Vector3d::Zero(),
            beta_index};
    const Eigen::Vector2d bogie_wheels[2] = {g.middle_wheel, g.front_wheel};
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d d_bogie = rotateDerivative(bogie, bogie_wheels[k]);
      w[1 + k] = {toBody(pivot + rotate(bogie, bogie_wheels[k]), lateral),
                  toBody(d_pivot + sign * d_bogie, 0.0), toBody(d_bogie, 0.0), beta_index};
    }
  }
}

}  // namespace

RockerBogieAttitudeModel::RockerBogieAttitudeModel(const terrain::TerrainSurface& surface,
                                                   const RockerBogieGeometry& geometry,
                                                   const RockerBogieSolverOptions& options)
    : surface_(surface), geometry_(geometry), options_(options) {
  if (!(geometry.half_track > 0.0) || !(geometry.wheel_radius >= 0.0)) {
    throw std::invalid_argument("rocker_bogie: half_track must be > 0 and wheel_radius >= 0");
  }
  if (!(options.tolerance > 0.0) || options.max_iterations < 1 ||
      !(options.max_joint_angle > 0.0) || !(options.max_tilt > 0.0)) {
    throw std::invalid_argument("rocker_bogie: invalid solver options");
  }
}

double RockerBogieAttitudeModel::samplingRadius() const {
  // The surface is sampled under the wheel centres; rotating the body only shortens their
  // planar offsets.
  const double to_pivot = geometry_.bogie_pivot.norm();
  const double in_plane =
      std::max({geometry_.rear_wheel.norm(), to_pivot + geometry_.front_wheel.norm(),
                to_pivot + geometry_.middle_wheel.norm()});
  return std::hypot(in_plane, geometry_.half_track);
}

Eigen::Matrix<double, 3, 6> RockerBogieAttitudeModel::wheelCentresInBody(
    const Eigen::Vector3d& suspension) const {
  WheelInBody wheels[kWheels];
  wheelsInBody(geometry_, suspension(0), suspension(1), suspension(2), wheels);
  Eigen::Matrix<double, 3, 6> centres;
  for (int k = 0; k < kWheels; ++k) centres.col(k) = wheels[k].position;
  return centres;
}

bool RockerBogieAttitudeModel::contactResiduals(const PlanarPose& pose, const Vector6& u,
                                                Vector6& residual, Matrix6* d_unknowns,
                                                Matrix63* d_pose) const {
  const double roll = u(1), pitch = u(2);
  const double cz = std::cos(pose.heading), sz = std::sin(pose.heading);
  const double cy = std::cos(pitch), sy = std::sin(pitch);
  const double cx = std::cos(roll), sx = std::sin(roll);
  Eigen::Matrix3d rz, ry, rx, drz, dry, drx;
  rz << cz, -sz, 0, sz, cz, 0, 0, 0, 1;
  drz << -sz, -cz, 0, cz, -sz, 0, 0, 0, 0;
  ry << cy, 0, -sy, 0, 1, 0, sy, 0, cy;  // Ry(-pitch): nose up for pitch > 0
  dry << -sy, 0, -cy, 0, 0, 0, cy, 0, -sy;
  rx << 1, 0, 0, 0, cx, -sx, 0, sx, cx;
  drx << 0, 0, 0, 0, -sx, -cx, 0, cx, -sx;
  const Eigen::Matrix3d rotation = rz * ry * rx;
  const Eigen::Matrix3d d_roll = rz * ry * drx;
  const Eigen::Matrix3d d_pitch = rz * dry * rx;
  const Eigen::Matrix3d d_heading = drz * ry * rx;
  const Eigen::Vector3d origin(pose.x, pose.y, u(0));

  WheelInBody wheels[kWheels];
  wheelsInBody(geometry_, u(3), u(4), u(5), wheels);
  const double r_w = geometry_.wheel_radius;
  for (int k = 0; k < kWheels; ++k) {
    const WheelInBody& w = wheels[k];
    const Eigen::Vector3d centre = origin + rotation * w.position;
    const std::optional<terrain::SurfaceDerivatives> ground =
        surface_.sampleWithHessian(centre.head<2>());
    if (!ground) return false;
    const double stretch = std::sqrt(1.0 + ground->gradient.squaredNorm());
    residual(k) = centre.z() - ground->height - r_w * stretch;
    // d(residual)/d(centre) = (-a, 1) with a the gradient of height + r_w * stretch.
    const Eigen::Vector2d a =
        ground->gradient + r_w * (ground->hessian * ground->gradient) / stretch;
    const auto along = [&a](const Eigen::Vector3d& d_centre) {
      return d_centre.z() - a.dot(d_centre.head<2>());
    };
    if (d_unknowns != nullptr) {
      Matrix6& j = *d_unknowns;
      j.row(k).setZero();
      j(k, 0) = 1.0;
      j(k, 1) = along(d_roll * w.position);
      j(k, 2) = along(d_pitch * w.position);
      j(k, 3) = along(rotation * w.d_rho);
      j(k, w.beta_index) = along(rotation * w.d_beta);
    }
    if (d_pose != nullptr) {
      (*d_pose)(k, 0) = -a.x();
      (*d_pose)(k, 1) = -a.y();
      (*d_pose)(k, 2) = along(d_heading * w.position);
    }
  }
  return true;
}

Vector6 RockerBogieAttitudeModel::coldStart(const PlanarPose& pose, bool& ok) const {
  Vector6 u = Vector6::Zero();
  const std::optional<terrain::HeightSample> ground = surface_.sample({pose.x, pose.y});
  ok = ground.has_value();
  if (!ok) return u;
  const double c = std::cos(pose.heading), s = std::sin(pose.heading);
  const PlaneAttitude plane = planeAttitude(ground->gradient.x() * c + ground->gradient.y() * s,
                                            -ground->gradient.x() * s + ground->gradient.y() * c);
  const double drop = -wheelCentresInBody(Eigen::Vector3d::Zero()).row(2).mean();
  u << ground->height + geometry_.wheel_radius + drop, plane.roll, plane.pitch, 0.0, 0.0, 0.0;
  return u;
}

AttitudeStatus RockerBogieAttitudeModel::solveFrom(const PlanarPose& pose, Vector6& u,
                                                   AttitudeResult& result) const {
  Vector6 residual;
  Matrix6 jacobian;
  Matrix63 d_pose;
  for (int iteration = 0; iteration <= options_.max_iterations; ++iteration) {
    if (!contactResiduals(pose, u, residual, &jacobian, &d_pose)) return AttitudeStatus::kNoTerrain;
    const Eigen::PartialPivLU<Matrix6> lu(jacobian);
    const double worst = residual.cwiseAbs().maxCoeff();
    if (worst < options_.tolerance) {
      if (u.segment<3>(3).cwiseAbs().maxCoeff() > options_.max_joint_angle ||
          u.segment<2>(1).cwiseAbs().maxCoeff() > options_.max_tilt) {
        return AttitudeStatus::kNoContact;
      }
      const Matrix63 du_dpose = -lu.solve(d_pose);
      if (!du_dpose.allFinite()) return AttitudeStatus::kNoContact;
      result.attitude = {u(0), u(1), u(2)};
      result.jacobian = du_dpose.topRows<3>();
      result.suspension = u.segment<3>(3);
      result.contact_residual = worst;
      result.iterations = iteration;
      return AttitudeStatus::kOk;
    }
    if (iteration == options_.max_iterations) break;
    Vector6 step = lu.solve(-residual);
    if (!step.allFinite()) return AttitudeStatus::kNoContact;
    const double scale = std::max({1.0, std::abs(step(0)) / kMaxHeightStep,
                                   step.tail<5>().cwiseAbs().maxCoeff() / kMaxAngleStep});
    u += step / scale;
    if (u.segment<3>(3).cwiseAbs().maxCoeff() > 2.0 * options_.max_joint_angle) {
      return AttitudeStatus::kNoContact;  // diverging into an impossible configuration
    }
  }
  return AttitudeStatus::kNoContact;
}

AttitudeStatus RockerBogieAttitudeModel::compute(const PlanarPose& pose,
                                                 AttitudeWorkspace& workspace,
                                                 AttitudeResult& result) const {
  AttitudeStatus status = AttitudeStatus::kNoContact;
  if (workspace.has_warm_start) {
    Vector6 u = workspace.warm_start;
    status = solveFrom(pose, u, result);
    if (status == AttitudeStatus::kOk) {
      workspace.warm_start = u;
      return status;
    }
  }
  bool ok = false;
  Vector6 u = coldStart(pose, ok);
  if (!ok) return AttitudeStatus::kNoTerrain;
  status = solveFrom(pose, u, result);
  workspace.has_warm_start = status == AttitudeStatus::kOk;
  if (workspace.has_warm_start) workspace.warm_start = u;
  return status;
}

}  // namespace terratraj::models
