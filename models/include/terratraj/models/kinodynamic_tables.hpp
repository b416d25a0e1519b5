#pragma once
// Building kinodynamic tables (003_...): physics-derived (appendix I, eqs. 1-3) and data-driven
// (top 1 % of the speeds per bin of a driving log), and the violation analysis of section IV.

#include <optional>
#include <vector>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/velocity_table.hpp"

namespace terratraj::models {

/// Default bin edges: pitch and roll from -0.4 to 0.4 rad in 16 bins of 0.05 rad; curvature
/// from -1 to 1 1/m in 20 bins of 0.1 1/m.
BinEdges defaultPitchEdges();
BinEdges defaultRollEdges();
BinEdges defaultCurvatureEdges();
/// n equal bins from lo to hi. Throws InputError unless lo < hi and n >= 1.
BinEdges uniformEdges(double lo, double hi, int bins, const std::string& what);

/// The vehicle in 003_... appendix I. Lengths [m], g [m/s^2], speeds [m/s].
struct PhysicsTableParameters {
  double gravity = 9.81;
  double half_track = 0.6;      ///< lateral offset of the wheels from the centre line
  double cog_height = 0.8;      ///< COG_z
  double friction = 0.6;        ///< C_friction
  double vehicle_length = 2.5;  ///< braking distance d_brake = 2 vehicle lengths
  double speed_cap = 12.0;      ///< every limit is capped here (003_... used 12 m/s)
};

/// Eq. 1 with the roll dependence of fig. 6a: tipping about the outer wheels of a turn, the
/// COG's horizontal offset from them is Y = half_track cos(roll) - sign(curvature) COG_z
/// sin(roll) (roll > 0, left side high, shrinks the margin of a left turn), and
/// v_max = sqrt(g Y / (|curvature| COG_z)), 0 when Y <= 0, the cap when curvature = 0.
double physicsRollCurvatureLimit(double roll, double curvature, const PhysicsTableParameters& p);
/// Eqs. 2-3 in this toolkit's sign (pitch > 0 nose up, 003_... uses the opposite):
/// F = g (C_friction cos(pitch) + sin(pitch)), v_max = sqrt(2 F d_brake cos(pitch)), 0 when
/// F <= 0; capped.
double physicsPitchLimit(double pitch, const PhysicsTableParameters& p);
/// Tables of the physics limits evaluated at the bin centres.
PitchSpeedTable physicsPitchTable(const BinEdges& pitch_edges, const PhysicsTableParameters& p);
RollCurvatureSpeedTable physicsRollCurvatureTable(const BinEdges& roll_edges,
                                                  const BinEdges& curvature_edges,
                                                  const PhysicsTableParameters& p);

/// How data-driven tables are built.
struct DataTableOptions {
  double top_fraction = 0.01;  ///< each bin holds the mean of its top fraction of speeds (>= 1)
  bool fill_empty = false;     ///< fill empty bins by linear interpolation between filled ones
};

/// The states a table is built from or checked against: (roll, pitch, curvature, v) per
/// sample. Curvature comes from the `curvature` column, else omega / v (0 when v = 0).
/// Throws InputError naming the missing column (roll, pitch, v; and curvature or omega).
struct DrivingStates {
  std::vector<double> roll, pitch, curvature, speed;
};
DrivingStates drivingStates(const Trajectory& log, const std::string& source_name);

/// Data-driven tables (003_... II.A). Throws InputError for invalid options.
PitchSpeedTable dataPitchTable(const DrivingStates& states, const BinEdges& pitch_edges,
                               const DataTableOptions& options);
RollCurvatureSpeedTable dataRollCurvatureTable(const DrivingStates& states,
                                               const BinEdges& roll_edges,
                                               const BinEdges& curvature_edges,
                                               const DataTableOptions& options);

/// Fractions of states faster than a table allows (by-bin lookup), per table and combined.
struct ViolationReport {
  std::size_t states = 0;
  std::optional<double> pitch_fraction;           ///< with a pitch table
  std::optional<double> roll_curvature_fraction;  ///< with a roll x curvature table
  double combined_fraction = 0.0;                 ///< states violating any given table
  double max_excess = 0.0;                        ///< largest v - v_max [m/s] (0 if none)
};
/// `tolerance` [m/s]: a state violates a table when v > v_max + tolerance.
ViolationReport analyseViolations(const DrivingStates& states, const PitchSpeedTable* pitch,
                                  const RollCurvatureSpeedTable* roll_curvature,
                                  double tolerance = 1e-9);

}  // namespace terratraj::models
