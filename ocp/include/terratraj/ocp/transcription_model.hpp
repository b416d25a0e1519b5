#pragma once
// TranscriptionModel: everything direct transcription needs at one point of a trajectory, in
// the state-space form of the rover on the terrain.
//
// A point's variables are w = (x, y, heading, v, omega, v', omega') [m, m, rad, m/s, rad/s,
// m/s^2, rad/s^2]: the state z = w(0..4) and the controls u = w(5..6). At a point the model
// gives
//   - the state rates f(z, u) (RoverKinematics::stateSpaceRates) and d f / d w;
//   - the path constraints g(w) <= 0 beyond the simple bounds on v, omega and v' (which the
//     transcription imposes as variable bounds): curvature, curvature rate, pitch, roll, the
//     smooth look-up tables (PathConstraints rows), and optionally the Segway RMP's platform
//     pitch (in place of the terrain pitch) and slope-dependent speed and acceleration bounds,
//     and a minimum clearance from impassable cells;
//   - the running cost l(w) = alpha (roll^2 + pitch^2) [slope dwell] + epsilon (v'^2 + omega'^2)
//     [control effort], so that J = t_f (1 + mean of l over the trajectory);
// each with its analytic gradient by w. Immutable; the caller owns the AttitudeWorkspace.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "terratraj/models/rover_kinematics.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/path_constraints.hpp"
#include "terratraj/terrain/clearance_map.hpp"

namespace terratraj::ocp {

/// Sizes of one transcription point.
inline constexpr int kStateSize = 5;
inline constexpr int kControlSize = 2;
inline constexpr int kPointSize = kStateSize + kControlSize;  // == kPathVariables

using PointVector = Eigen::Matrix<double, kPointSize, 1>;
using StateVector = Eigen::Matrix<double, kStateSize, 1>;
using ConstraintJacobian = Eigen::Matrix<double, Eigen::Dynamic, kPointSize>;

/// The Segway RMP's extra constraints (001_... III.C): its platform pitch (from the look-up of
/// acceleration and slope) replaces the terrain pitch in the pitch rows, and the speed and
/// acceleration are bounded by the slope look-ups. The rows take the look-ups' C1 versions
/// (models::SegwayPitchResponse::smoothPitch, SegwaySlopeBounds::optimiserSpeedLimit and
/// optimiserAccelerationLimit: second derivatives for the exact Hessian, a way back from
/// undrivable slopes); accumulateViolation() judges by the look-ups themselves.
struct SegwayConstraints {
  models::SegwayLookups lookups;
  /// The slope-dependent speed and acceleration bounds times this, in (0, 1] (the verification
  /// rounds' margin; 1: the look-ups as they are).
  double bound_scale = 1.0;
};

/// Keeping away from lethal and no-data cells (docs/optimal-control.md): a smooth constraint
/// clearance(x, y) >= min_clearance on the bilinear distance transform of the lethal layer.
struct ClearanceConstraint {
  const terrain::ClearanceMap* map = nullptr;  ///< not owned; null: no clearance constraint
  double min_clearance = 0.0;                  ///< [m]
};

/// What a TranscriptionModel adds to the rover's limits and cost.
struct TranscriptionModelOptions {
  double control_effort_weight = 0.0;       ///< epsilon [s^4 / m^2 and s^4 / rad^2], >= 0
  std::optional<SegwayConstraints> segway;  ///< the Segway RMP's constraints
  ClearanceConstraint clearance;
};

/// Everything at one point (the workspace of TranscriptionModel::evaluate; preallocated by
/// TranscriptionModel::makeEvaluation, reused without allocation).
struct PointEvaluation {
  StateVector rate = StateVector::Zero();                       ///< f(z, u)
  Eigen::Matrix<double, kStateSize, kPointSize> rate_jacobian;  ///< d f / d w
  Eigen::VectorXd constraints;                                  ///< g(w), constraintCount() rows
  ConstraintJacobian constraint_jacobian;                       ///< d g / d w
  double running_cost = 0.0;                                    ///< l(w)
  PointVector running_cost_gradient = PointVector::Zero();      ///< d l / d w
  PathPoint point;              ///< the point as PathConstraints sees it (for violations)
  double platform_pitch = 0.0;  ///< Segway only [rad]
  double slope = 0.0;           ///< terrain pitch along the heading [rad]
  double clearance = 0.0;       ///< [m] (only with a clearance constraint)
  // Scratch for PathConstraints.
  Eigen::VectorXd path_values;
  ConstraintJacobian path_jacobian;
};

/// The rover, its limits and the running cost at single points.
class TranscriptionModel {
 public:
  /// `vehicle` (and the clearance map, when given) must outlive the model.
  TranscriptionModel(const models::TerrainFollowingModel& vehicle,
                     const BoundaryValueProblem& problem,
                     const TranscriptionModelOptions& options = {});

  /// Rows of g per point.
  int constraintCount() const { return count_; }
  /// The limit a row of g enforces ("kappa_max", "pitch_max", "clearance", ...).
  const char* constraintName(int row) const;
  /// A workspace sized for this model.
  PointEvaluation makeEvaluation() const;

  /// Evaluates the point `w`. Returns the attitude status (anything but kOk: off the map, no
  /// contact; `out` is then unspecified). Never throws; no allocation.
  models::AttitudeStatus evaluate(const PointVector& w, models::AttitudeWorkspace& workspace,
                                  PointEvaluation& out) const;

  /// Violations of every limit at an evaluated point, in the limits' own units, folded into
  /// `worst` (the re-simulation's check; clearance is reported as "clearance" in m).
  void accumulateViolation(const PointEvaluation& point, LimitViolation& worst) const;

  const BoundaryValueProblem& problem() const { return problem_; }
  const TranscriptionModelOptions& options() const { return options_; }
  const models::RoverKinematics& kinematics() const { return kinematics_; }

 private:
  models::RoverKinematics kinematics_;
  BoundaryValueProblem problem_;
  TranscriptionModelOptions options_;
  PathConstraints path_;
  int path_rows_;    // rows taken from PathConstraints (its rows 6..)
  int segway_rows_;  // 3 with the Segway, else 0
  int count_;
};

/// The first PathConstraints row a TranscriptionModel uses: rows 0-5 (speed, acceleration,
/// yaw rate) are variable bounds in the transcription.
inline constexpr int kFirstPathRow = 6;

}  // namespace terratraj::ocp
