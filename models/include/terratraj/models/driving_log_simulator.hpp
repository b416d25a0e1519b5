#pragma once
// A simulated expert driver, for building data-driven tables (003_...) where no real driving
// logs exist.
//
// The vehicle (point attitude model) drives on a generated `hills` terrain. The driver:
//  - steers: a new target curvature, uniform in [-max_curvature, max_curvature], every
//    `steer_period` seconds, approached at `curvature_rate`; near the map edge it turns back
//    toward the centre;
//  - avoids a region: it never turns harder than `avoid_curvature` while the roll works
//    against the turn (sign(curvature) * roll > avoid_roll: the outer wheels downhill), so the
//    roll x curvature bins beyond that stay empty;
//  - drives fast: its comfort speed is min(speed_cap, sqrt(lateral_acceleration / |curvature|)),
//    reduced downhill by downhill_slowdown * max(0, -pitch) / 0.4, and it drives at that speed
//    times (1 - noise * u), u uniform in [0, 1] (so the top of each bin is the comfort speed);
//    speed changes are limited to `acceleration`.
// Deterministic for a seed. Rows are the contract's trajectory columns at `sample_period`.

#include <cstdint>

#include "terratraj/models/trajectory.hpp"

namespace terratraj::models {

/// The simulated driver and its course. Units SI.
struct DrivingLogOptions {
  std::uint64_t seed = 1;
  double duration = 600.0;            ///< [s]
  double sample_period = 0.1;         ///< [s] one row per period
  int terrain_size = 256;             ///< cells per side of the generated hills
  double terrain_cell = 0.5;          ///< [m]
  double speed_cap = 8.0;             ///< [m/s]
  double lateral_acceleration = 2.0;  ///< [m/s^2] comfort limit in turns
  double downhill_slowdown = 0.6;     ///< fraction of speed given up at 0.4 rad nose down
  double acceleration = 1.5;          ///< [m/s^2] |dv/dt| limit
  double noise = 0.3;                 ///< speed below comfort: up to this fraction
  double max_curvature = 0.8;         ///< [1/m]
  double curvature_rate = 0.4;        ///< [1/(m s)]
  double steer_period = 2.0;          ///< [s]
  double avoid_roll = 0.1;            ///< [rad]
  double avoid_curvature = 0.4;       ///< [1/m]
};

/// Simulates a driving log. Throws InputError for invalid options.
Trajectory simulateDrivingLog(const DrivingLogOptions& options);

}  // namespace terratraj::models
