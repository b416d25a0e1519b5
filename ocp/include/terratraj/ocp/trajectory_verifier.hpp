#pragma once
// Independent re-simulation of a solver's final controls: the figures of the solve report
// (terminal errors, cost, attitude extremes, constraint violation) and the trajectory CSV come
// from here, not from the solver's own claim. A separate integrator at tighter tolerances
// samples the trajectory; every sample is checked against the limits, the look-up tables and
// the lethal layer.

#include <Eigen/Core>
#include <string>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/path_constraints.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::ocp {

/// How to re-simulate.
struct VerificationOptions {
  double sample_dt = 0.02;            ///< trajectory sample spacing [s], > 0
  double relative_tolerance = 1e-10;  ///< CVODES
  double absolute_tolerance = 1e-12;  ///< CVODES [m, rad]
};

/// What the re-simulation found.
struct VerifiedTrajectory {
  bool ok = false;  ///< false: the trajectory could not be re-simulated (message)
  /// When not ok: the re-simulation left the terrain (off the map, or where no data leaves the
  /// surface undefined) rather than failing otherwise.
  bool off_terrain = false;
  std::string message;
  models::Trajectory trajectory;  ///< samples every sample_dt and at t_f (the last row)
  Eigen::Vector3d terminal_error = Eigen::Vector3d::Zero();  ///< reached - goal, heading wrapped
  double final_time = 0.0;                                   ///< [s]
  double cost = 0.0;                                         ///< J re-integrated [s]
  double slope_dwell = 0.0;  ///< integral of roll^2 + pitch^2 dt [rad^2 s]
  double length = 0.0;       ///< planar path length [m]
  double max_abs_pitch = 0.0, max_abs_roll = 0.0, max_speed = 0.0;
  /// Re-integrated final speed and yaw rate minus the goal's (transcription only) [m/s, rad/s].
  Eigen::Vector2d terminal_speed_error = Eigen::Vector2d::Zero();
  LimitViolation violation;  ///< largest, over the samples ("lethal" when a sample is on one)
};

/// Re-simulates `q` (ParametricControls layout of `problem`) on `vehicle`. `map`, when not
/// null, supplies the lethal layer. Never throws.
VerifiedTrajectory verifyParametricSolution(const models::TerrainFollowingModel& vehicle,
                                            const BoundaryValueProblem& problem,
                                            const Eigen::VectorXd& q,
                                            const terrain::ElevationMap* map,
                                            const VerificationOptions& options = {});

/// Re-simulates a direct-transcription solution: v and omega re-integrated from the start with
/// the interpolated controls (TranscriptionSolution::controlsAt), the pose by CVODES, every
/// sample checked against the model's limits (including the Segway's and the clearance) and
/// the lethal layer of `map` when not null. Never throws.
VerifiedTrajectory verifyTranscriptionSolution(const TranscriptionModel& model,
                                               const TranscriptionSolution& solution,
                                               const terrain::ElevationMap* map,
                                               const VerificationOptions& options = {});

}  // namespace terratraj::ocp
