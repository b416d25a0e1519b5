#include "terratraj/models/rover_kinematics.hpp"

#include <cmath>

namespace terratraj::models {

AttitudeStatus RoverKinematics::rates(const Eigen::Vector3d& state, double v, double omega,
                                      AttitudeWorkspace& workspace, RoverRates& out) const {
  const AttitudeStatus status =
      model_->compute({state.x(), state.y(), state.z()}, workspace, out.attitude);
  if (status != AttitudeStatus::kOk) return status;
  const double ch = std::cos(state.z()), sh = std::sin(state.z());
  const double cp = std::cos(out.attitude.attitude.pitch),
               sp = std::sin(out.attitude.attitude.pitch);
  const double cr = std::cos(out.attitude.attitude.roll), sr = std::sin(out.attitude.attitude.roll);
  const Eigen::RowVector3d d_roll = out.attitude.jacobian.row(1);
  const Eigen::RowVector3d d_pitch = out.attitude.jacobian.row(2);
  const Eigen::RowVector3d d_heading(0.0, 0.0, 1.0);
  out.rate << v * ch * cp, v * sh * cp, omega * cr / cp;
  out.d_state.row(0) = v * (-sh * cp * d_heading - ch * sp * d_pitch);
  out.d_state.row(1) = v * (ch * cp * d_heading - sh * sp * d_pitch);
  out.d_state.row(2) = omega * (-sr / cp * d_roll + cr * sp / (cp * cp) * d_pitch);
  out.d_input << ch * cp, 0.0, sh * cp, 0.0, 0.0, cr / cp;
  return AttitudeStatus::kOk;
}

AttitudeStatus RoverKinematics::stateSpaceRates(const Eigen::Matrix<double, 5, 1>& state,
                                                const Eigen::Vector2d& control,
                                                AttitudeWorkspace& workspace,
                                                RoverStateSpaceRates& out) const {
  RoverRates reduced;
  const AttitudeStatus status = rates(state.head<3>(), state(3), state(4), workspace, reduced);
  if (status != AttitudeStatus::kOk) return status;
  out.rate << reduced.rate, control;
  out.d_state.setZero();
  out.d_state.topLeftCorner<3, 3>() = reduced.d_state;
  out.d_state.topRightCorner<3, 2>() = reduced.d_input;
  out.d_control.setZero();
  out.d_control.bottomRows<2>().setIdentity();
  out.attitude = reduced.attitude;
  return AttitudeStatus::kOk;
}

}  // namespace terratraj::models
