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
  const std::vector<double>& slopes() const { return slopes_; }

 private:
  std::vector<double> slopes_, v_max_, a_max_;
};

/// Both look-ups.
struct SegwayLookups {
  SegwayPitchResponse pitch_response;
  SegwaySlopeBounds bounds;
};

/// The built-in stand-ins described above.
SegwayLookups defaultSegwayLookups();
/// Reads the two files. Throws InputError naming the file and key at fault.
SegwayLookups readSegwayLookups(const std::filesystem::path& pitch_response_file,
                                const std::filesystem::path& slope_bounds_file);

}  // namespace terratraj::models
