#pragma once
// PlannerState: the state of a roadmap node (001_... III.D): position and heading in the local
// map frame, forward speed and the curvature of the path, from which the yaw rate follows.

#include <Eigen/Core>

namespace terratraj::search {

/// A vehicle state as the planner sees it. Value type.
struct PlannerState {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< local map frame (x east, y north) [m]
  double heading = 0.0;    ///< map heading [rad], 0 along +x, counter-clockwise
  double v = 0.0;          ///< forward speed along the surface [m/s], >= 0
  double curvature = 0.0;  ///< curvature of the path in the tangent plane [1/m]

  /// Yaw rate about the body z axis [rad/s]: v * curvature.
  double omega() const { return v * curvature; }
};

}  // namespace terratraj::search
