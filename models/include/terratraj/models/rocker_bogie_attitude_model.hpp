#pragma once
// RockerBogieAttitudeModel: the rocker-bogie suspension of the Rocky 7 rover (004_... 3.3).
//
// Six unknowns u = (z, roll, pitch, rho, beta1, beta2) make all six wheels touch the terrain:
// the body (reference point midway between the two rocker pivots) sits at height z with roll
// and pitch; the left rocker turns by +rho about the body's lateral axis and the right by -rho
// (a differential); each rocker carries the rear wheel and, at its front end, a bogie pivot; the
// bogies (angles beta1 left, beta2 right, relative to their rocker) carry the middle and front
// wheels. Wheel k touches when its centre c_k lies r_w above the local tangent plane of the
// terrain: c_k,z - g(c_k,xy) - r_w sqrt(1 + |grad g|^2) = 0 (exact for a spherical wheel on a
// locally planar patch). Newton's method solves the six equations to `tolerance` (default
// 1e-6 m, far below the paper's millimetre), warm-started from the workspace's last solution.
// The derivatives of (z, roll, pitch) with respect to (x, y, heading) come from implicit
// differentiation of the contact equations: du/dpose = -J_u^-1 J_pose.
//
// Default geometry: Rocky 7 is 48 x 64 x 32 cm overall (JPL's description of the rover); the
// link lengths below are chosen to fit that envelope (wheel centres 0.25 m ahead of and behind
// the middle wheel, 0.40 m track, 0.13 m wheels, pivots 0.12 m above the wheel centres). They
// are documented estimates, not published drawings; pass your own RockerBogieGeometry.

#include <Eigen/Core>

#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::models {

/// Link geometry [m]. 2-D vectors are (forward, up) offsets in the plane of a rocker.
struct RockerBogieGeometry {
  double half_track = 0.20;                       ///< pivot's lateral offset, > 0
  double wheel_radius = 0.065;                    ///< >= 0
  Eigen::Vector2d rear_wheel = {-0.25, -0.12};    ///< rear wheel centre, rocker frame
  Eigen::Vector2d bogie_pivot = {0.10, -0.06};    ///< bogie pivot, rocker frame
  Eigen::Vector2d front_wheel = {0.15, -0.06};    ///< front wheel centre, bogie frame
  Eigen::Vector2d middle_wheel = {-0.10, -0.06};  ///< middle wheel centre, bogie frame
};

/// Newton settings.
struct RockerBogieSolverOptions {
  double tolerance = 1e-6;       ///< largest wheel contact error accepted [m], > 0
  int max_iterations = 25;       ///< per attempt (warm, then cold), >= 1
  double max_joint_angle = 0.8;  ///< |rho|, |beta| beyond this [rad] = the suspension cannot reach
  double max_tilt = 1.2;         ///< |roll|, |pitch| beyond this [rad] = no resting attitude
};

/// Attitude and suspension configuration of a rocker-bogie rover.
class RockerBogieAttitudeModel final : public TerrainFollowingModel {
 public:
  /// Throws std::invalid_argument for a degenerate geometry or invalid options.
  RockerBogieAttitudeModel(const terrain::TerrainSurface& surface,
                           const RockerBogieGeometry& geometry = {},
                           const RockerBogieSolverOptions& options = {});

  AttitudeStatus compute(const PlanarPose& pose, AttitudeWorkspace& workspace,
                         AttitudeResult& result) const override;
  const char* name() const override { return "rocker_bogie"; }
  const terrain::TerrainSurface& surface() const override { return surface_; }
  /// Bounds each wheel centre's reach for any joint angles (a rocker or bogie link turns about
  /// its pivot, so the wheel stays within its links' summed lengths in the rocker's plane),
  /// beside half the track [m]: the surface is sampled under the wheel centres.
  double samplingRadius() const override;
  const RockerBogieGeometry& geometry() const { return geometry_; }

  /// Wheel centres in the body frame for a suspension configuration (rho, beta1, beta2), in the
  /// order left rear, left middle, left front, right rear, right middle, right front.
  Eigen::Matrix<double, 3, 6> wheelCentresInBody(const Eigen::Vector3d& suspension) const;

  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Matrix63 = Eigen::Matrix<double, 6, 3>;
  /// Contact errors [m] of the six wheels at unknowns u for a pose, with d/du and d/dpose
  /// (either may be null). false where a wheel is off the surface. Public for tests.
  bool contactResiduals(const PlanarPose& pose, const Vector6& u, Vector6& residual,
                        Matrix6* d_unknowns, Matrix63* d_pose) const;

 private:
  Vector6 coldStart(const PlanarPose& pose, bool& ok) const;
  AttitudeStatus solveFrom(const PlanarPose& pose, Vector6& u, AttitudeResult& result) const;

  terrain::TerrainSurface surface_;
  RockerBogieGeometry geometry_;
  RockerBogieSolverOptions options_;
};

}  // namespace terratraj::models
