#pragma once
// ExtensionIntegrator: one PRM extension (001_... IV.B-C): steer from a state toward a target
// with the continuous-curvature law, integrating on tangent-plane patches of length delta_g
// (001_... III.B), check every constraint along the way, and give the path its bang-bang speed
// profile. A failed extension is "trapped".
//
// Integration: at each step the patch is the tangent plane of the surface under the vehicle,
// oriented along its heading (terrain::TangentPlanePatch); the vehicle moves delta_g along the
// plane with the curvature varying linearly (exact clothoid arc, by Simpson sub-steps), then
// enters the next patch at the surface point under its end position, its map heading taken
// from the direction of motion. Checked at every sample: the map (no data, off the map), the
// lethal layer (every cell the segment between two samples touches, conservatively), pitch and
// roll from the vehicle's attitude model (constraints (3), (4)); near no data, also that the
// vehicle can be placed along the chord between two samples (the surface is undefined beside
// no data, and a path's rows are joined by chords). Speed-dependent constraints
// become speed caps for the profile: v_max (5), omega_max and kappa_max (1), the curvature
// rate sigma_max (1), and the tables (v_max by pitch, by roll x curvature); the profile keeps
// |dv/dt| <= a_max (6). Not allocating once its buffers have grown.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/search/continuous_curvature_steering.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/speed_profile.hpp"

namespace terratraj::search {

/// Outcome of one extension. Everything except kReached and kTruncated is "trapped".
enum class ExtensionStatus {
  kReached,      ///< came within the end tolerance of the target
  kTruncated,    ///< stopped at the maximum length (the end state is still a valid node)
  kOffMap,       ///< left the map or came near no-data cells
  kLethal,       ///< touched a lethal or no-data cell
  kAttitude,     ///< the vehicle cannot rest on the terrain there (attitude model failure)
  kPitch,        ///< |pitch| > pitch_max
  kRoll,         ///< |roll| > roll_max
  kSpeed,        ///< no admissible speed profile (cannot brake, start above a cap, stall)
  kUnreachable,  ///< the target lies inside the turning circle (the turn exceeded 1.5 pi)
};

/// Name of an ExtensionStatus ("reached", "truncated", "off_map", ...).
const char* extensionStatusName(ExtensionStatus status);
/// Whether an extension produced a usable path (kReached or kTruncated).
inline bool extensionSucceeded(ExtensionStatus status) {
  return status == ExtensionStatus::kReached || status == ExtensionStatus::kTruncated;
}

/// What to steer toward. Stored with each roadmap edge: re-running the extension from the
/// parent's state reproduces the edge exactly (the integration is deterministic).
struct ExtensionRequest {
  Eigen::Vector2d target = Eigen::Vector2d::Zero();  ///< local map frame [m]
  double target_speed = 0.0;  ///< speed wished at the end [m/s] (the profile brakes to it)
  double turn_speed = 1.0;    ///< speed the turn is shaped for [m/s] (ContinuousCurvatureSteering)
  double max_length = 10.0;   ///< stop after this arc length [m] (kTruncated)
};

/// One sample of an extension's path. Units as in models::TrajectorySample.
struct PathPoint {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< [m]
  double z = 0.0;          ///< height of the vehicle's reference point [m]
  double heading = 0.0;    ///< map heading [rad]
  double roll = 0.0;       ///< [rad]
  double pitch = 0.0;      ///< [rad]
  double curvature = 0.0;  ///< in-plane curvature [1/m]
  double s = 0.0;          ///< arc length from the start along the surface [m]
  double v = 0.0;          ///< speed [m/s] (after the speed profile)
  double t = 0.0;          ///< time from the start [s]
};

/// A path point as a trajectory row at time t0 + point.t (omega = v * curvature).
models::TrajectorySample trajectorySample(const PathPoint& point, double t0);

/// The result of one extension. Reuse one object: its buffers are kept.
struct Extension {
  ExtensionStatus status = ExtensionStatus::kUnreachable;
  std::vector<PathPoint> points;  ///< first = the start state; valid when succeeded
  PlannerState end;               ///< the state at the last point (valid when succeeded)
  double duration = 0.0;          ///< [s]
  double length = 0.0;            ///< arc length [m]
};

/// Settings of the integration.
struct IntegrationSettings {
  double delta_g = 0.125;  ///< patch length [m] (001_...: a fraction of the cell size), > 0
  /// An extension has reached its target when it ends within this fraction of delta_g of it.
  double end_tolerance_fraction = 0.5;
};

/// Runs extensions for one planner (one per thread: it owns scratch buffers).
class ExtensionIntegrator {
 public:
  /// `problem` must outlive the integrator.
  ExtensionIntegrator(const PlanningProblem& problem, const IntegrationSettings& settings);

  /// Steers from `from` toward `request.target`; writes `out` and returns its status.
  ExtensionStatus extend(const PlannerState& from, const ExtensionRequest& request, Extension& out);

  /// The patch length and end tolerance in use.
  const IntegrationSettings& settings() const { return settings_; }

 private:
  // Attitude at a pose into `point`; false (with `status`) when the vehicle cannot rest there
  // or breaks the pitch / roll limits.
  bool attitudeAt(PathPoint& point, ExtensionStatus& status);
  // Whether the straight segment between two positions touches a lethal or no-data cell.
  bool segmentBlocked(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;
  // Whether the vehicle can be placed all along the chord between two samples (every quarter
  // cell, heading interpolated), checked only where either end's cell is near no data: a
  // path's rows are joined by chords (a transcription's guess interpolates them), and beside no
  // data the surface is undefined within a few cells (TerrainSurface::stencilReach).
  bool chordPlaceable(const PathPoint& a, const PathPoint& b);
  // Speed cap [m/s] at a sample from v_max, omega_max and the tables.
  double pointCap(const PathPoint& point) const;

  const PlanningProblem* problem_;
  IntegrationSettings settings_;
  ContinuousCurvatureSteering steering_;
  models::AttitudeWorkspace workspace_;
  models::AttitudeResult attitude_;
  SpeedProfile profile_;
  std::vector<double> segment_lengths_;
  std::vector<double> caps_;
  /// Per cell, 1 within the surface's stencil reach plus the vehicle's sampling radius and a
  /// slack for the chord's length of a no-data cell (terrain::noDataBand); empty when the map
  /// has no no data.
  std::vector<std::uint8_t> near_no_data_;
  models::AttitudeWorkspace chord_workspace_;  // apart: the samples' warm starts stay as they were
  models::AttitudeResult chord_attitude_;
  std::vector<double> chord_fractions_;  // where along a chord its points are checked
};

}  // namespace terratraj::search
