#pragma once
// Motion primitives of a state lattice (004_... fig. 4; 002_...): short trajectories between
// lattice states, generated once on flat ground by the parametric boundary-value solver and
// replayed from any lattice node by translation.
//
// A lattice state is (i, j, heading index k): position origin + resolution * (i, j) in the local
// map frame, heading 2 pi k / heading_count. A primitive leaves a state of heading index
// `start_heading` and ends `offset` lattice cells away with heading index `end_heading`. Its
// curvature is zero at both ends, so primitives chain with continuous curvature.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/vehicle_limits.hpp"

namespace terratraj::search {

/// The lattice's discretisation. Value type.
struct LatticeSpec {
  double resolution = 0.5;  ///< spacing of lattice positions [m], > 0
  int heading_count = 16;   ///< headings per turn, >= 4 (any count; uniform in angle)

  /// Heading of index k [rad], in [0, 2 pi); k is taken modulo heading_count.
  double headingAngle(int k) const;
  /// The index whose heading is nearest to `heading` [rad] (any value; NaN gives 0).
  int nearestHeading(double heading) const;
  /// k modulo heading_count, in [0, heading_count).
  int wrapHeading(int k) const;
  /// Why the spec is unusable ("resolution ...", "heading_count ..."), or std::nullopt.
  std::optional<std::string> validate() const;
};

/// One sample of a primitive, relative to its start node (position (0, 0)).
struct PrimitiveSample {
  double s = 0.0;          ///< arc length from the start [m]
  double t = 0.0;          ///< time at the generation speed [s]
  double x = 0.0;          ///< [m], relative to the start node
  double y = 0.0;          ///< [m]
  double heading = 0.0;    ///< map heading [rad] (continuous along the primitive, not wrapped)
  double curvature = 0.0;  ///< [1/m]
};

/// One primitive. Samples are spaced at most PrimitiveSet::sample_spacing apart; the first is
/// (0, 0) at the start heading, the last exactly at offset * resolution.
struct MotionPrimitive {
  int start_heading = 0;                             ///< heading index at the start
  int end_heading = 0;                               ///< heading index at the end
  Eigen::Vector2i offset = Eigen::Vector2i::Zero();  ///< end minus start [lattice cells]
  double length = 0.0;                               ///< arc length [m]
  double duration = 0.0;                             ///< at the generation speed [s]
  double max_abs_curvature = 0.0;                    ///< [1/m]
  double max_abs_curvature_rate = 0.0;               ///< |d curvature / ds| [1/m^2]
  std::vector<PrimitiveSample> samples;
};

/// How a set was generated (stored with it so that a file can be checked against a lattice and
/// a vehicle before use).
struct PrimitiveGenerationInfo {
  double speed = 1.0;               ///< constant speed of the boundary-value problems [m/s]
  double kappa_max = 1.0;           ///< curvature bound used [1/m]
  double sigma_max = 0.5;           ///< curvature-rate bound used [1/(m s)]
  double omega_max = 1.0;           ///< yaw-rate bound used [rad/s]
  std::vector<int> turns;           ///< heading-index changes requested per start heading
  double generation_time_ms = 0.0;  ///< wall clock of the generation [ms]
  int solves = 0;                   ///< boundary-value solves run
  int failures = 0;                 ///< of which did not converge
};

/// A lattice's primitives, grouped by start heading. Value type.
struct PrimitiveSet {
  LatticeSpec lattice;
  double sample_spacing = 0.05;  ///< largest arc length between samples [m]
  PrimitiveGenerationInfo generation;
  /// by_heading[k]: the primitives leaving heading index k (heading_count lists).
  std::vector<std::vector<MotionPrimitive>> by_heading;

  /// Number of primitives over all headings.
  std::size_t size() const;
  /// Why the set cannot serve `lattice` with a vehicle of `limits` (a message naming the
  /// primitive and field at fault: resolution or heading count differ, a heading without
  /// primitives, samples that do not start at the node or end at the offset, indices out of
  /// range, curvature above kappa_max), or std::nullopt when it can. `limits` may be null.
  std::optional<std::string> checkAgainst(const LatticeSpec& lattice,
                                          const models::VehicleLimits* limits) const;
};

}  // namespace terratraj::search
