#pragma once
// The Segway RMP's look-up functions (001_... III.C): its platform pitch response to
// acceleration and slope, and its slope-dependent speed and acceleration bounds.
//
// Kobilarov & Sukhatme measured these on the robot; the measurements are not published. The
// built-in defaults (defaultSegwayLookups()) are documented stand-ins, also shipped as editable
// files in models/data/segway_rmp/ (docs/segway-rmp.md):
//  - pitch response: a balancing platform leans so that gravity and inertia balance,
//    pitch = -atan((a + g sin(slope)) / (g cos(slope))) (pitch > 0 nose up; leaning forward
//    to accelerate or to climb is negative);
//  - bounds: 3.5 m/s and 2 m/s^2 on the level (the paper's figures), v_max falling linearly
//    from 5 degrees to 1 m/s at the 17 degree climbing limit, a_max = 2 - g sin|slope| / 2,
//    both 0 beyond 17 degrees.
// Both are grids of values joined by (bi)linear interpolation, clamped outside the grid.
//
// JSON (all angles in radians, slopes > 0 uphill along the heading):
//   {"kind": "segway_pitch_response", "acceleration_mps2": [...], "slope_rad": [...],
//    "pitch_rad": [[...], ...]}        // one row per acceleration, one column per slope
//   {"kind": "segway_slope_bounds", "slope_rad": [...], "v_max": [...], "a_max": [...]}

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "terratraj/models/velocity_table.hpp"

namespace terratraj::models {

/// Platform pitch [rad] by acceleration [m/s^2] and slope [rad], bilinear on a grid.
class SegwayPitchResponse {
 public:
  SegwayPitchResponse() = default;
  /// Throws InputError unless both axes strictly increase (>= 2 points) and pitch is
  /// (accelerations x slopes) of finite values.
  SegwayPitchResponse(std::vector<double> accelerations, std::vector<double> slopes,
                      Eigen::MatrixXd pitch);
  /// Pitch at (acceleration, slope), clamped to the grid.
  double pitch(double acceleration, double slope) const;
  /// The same grid as optimisers take it [rad], continuously differentiable: the tensor product
  /// of cubic Hermite pieces through the grid values (their slopes the differences of the
  /// neighbours), continued linearly beyond the grid; its derivatives into *d_acceleration
  /// [rad s^2 / m] and *d_slope when not null. Within the grid it departs from pitch() by the
  /// curvature of the data between grid points (for the defaults, under 0.3 deg).
  double smoothPitch(double acceleration, double slope, double* d_acceleration = nullptr,
                     double* d_slope = nullptr) const;
  const std::vector<double>& accelerations() const { return accelerations_; }
  const std::vector<double>& slopes() const { return slopes_; }
  const Eigen::MatrixXd& values() const { return pitch_; }

 private:
  std::vector<double> accelerations_, slopes_;
  Eigen::MatrixXd pitch_;
};

/// v_max [m/s] and a_max [m/s^2] by slope [rad], linear on a grid.
class SegwaySlopeBounds {
 public:
  SegwaySlopeBounds() = default;
  /// Throws InputError unless slopes strictly increase (>= 2 points) and both bounds have one
  /// finite value >= 0 per slope.
  SegwaySlopeBounds(std::vector<double> slopes, std::vector<double> v_max,
                    std::vector<double> a_max);
  double speedLimit(double slope) const;
  double accelerationLimit(double slope) const;
  /// The largest slope magnitude [rad] below which both bounds are positive, uphill and
  /// downhill: the first zero of either look-up on each side of 0 (20 deg for the defaults);
  /// 0 when a bound is 0 on the level; infinity when neither ever reaches 0. On steeper slopes
  /// the Segway can neither move nor change its speed.
  double drivableSlope() const;
  /// speedLimit() [m/s] and accelerationLimit() [m/s^2] as an optimiser's constraints take
  /// them (continuously differentiable, and with a direction back to drivable ground):
  ///  - up to the first slope, on the side of 0 of `slope`, where either bound is 0 (the edge of
  ///    drivable ground), the look-ups with every corner rounded over +-0.5 deg (by a parabola
  ///    tangent to both pieces, below the look-up where it bends down; where it bends up, less
  ///    a C1 bump over the same +-0.5 deg that keeps it below the look-up too), never above the
  ///    look-ups;
  ///  - beyond the edge, the bound's last piece before it continued below 0 (descending by at
  ///    least 1 per radian). The look-ups are flat at 0 there, which gives a point on an
  ///    undrivable slope no direction back; continued, its row is broken with a gradient
  ///    towards drivable ground. Beyond the edge the Segway cannot drive with either.
  /// A solution is judged by speedLimit() and accelerationLimit() (the verdict).
  /// Their derivatives by slope into *d_slope when not null.
  double optimiserSpeedLimit(double slope, double* d_slope = nullptr) const;
  double optimiserAccelerationLimit(double slope, double* d_slope = nullptr) const;
  const std::vector<double>& slopes() const { return slopes_; }

 private:
  void buildOptimiserKnots();

  std::vector<double> slopes_, v_max_, a_max_;
  /// The optimisers' bounds: the grid between the edges, the continued pieces beyond them.
  std::vector<double> optimiser_slopes_, optimiser_v_, optimiser_a_;
};

/// Both look-ups.
struct SegwayLookups {
  SegwayPitchResponse pitch_response;
  SegwaySlopeBounds bounds;
};

/// The Segway's speed bound by slope as a pitch table (PitchSpeedTable), for the searches, which
/// take speed limits by pitch that way (the pitch of a terrain-following pose is the slope
/// along its heading). Never faster than `bounds` anywhere: each interval between the bounds'
/// slopes is cut into bins of at most `bin_width` [rad], each holding the lower bound of its two
/// ends (the bound is linear between them); beyond the outermost slopes the outermost values
/// hold, as in speedLimit(). With `also` (a user's pitch table), the table is the lower of the
/// two in every bin (their edges merged). The default bins, 0.25 deg, lose at most 0.083 m/s of
/// the defaults' bound (on its steepest piece, 1 m/s over the 3 deg from 17 to 20 deg). Throws
/// InputError unless bin_width > 0.
PitchSpeedTable slopeSpeedTable(const SegwaySlopeBounds& bounds, const PitchSpeedTable* also,
                                double bin_width = 0.25 * 3.14159265358979323846 / 180.0);

/// The built-in stand-ins described above.
SegwayLookups defaultSegwayLookups();
/// Reads the two files. Throws InputError naming the file and key at fault.
SegwayLookups readSegwayLookups(const std::filesystem::path& pitch_response_file,
                                const std::filesystem::path& slope_bounds_file);

}  // namespace terratraj::models
