#pragma once
// Problem sets of 004_... shared by the tests and the convergence benchmark: the flat 45-goal
// fan (fig. 5), the 35-node / 94-edge lattice on rough terrain (fig. 4), and the single hill
// of the slope-dwell experiment (figs. 6-7).

#include <cmath>
#include <random>
#include <vector>

#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::ocp::fixtures {

/// Limits loose enough that the unconstrained parametric solvers are judged on convergence.
inline models::VehicleLimits looseLimits() {
  models::VehicleLimits limits;
  limits.v_max = 2.0;
  limits.a_max = 5.0;
  limits.omega_max = 5.0;
  limits.kappa_max = 10.0;
  limits.sigma_max = 100.0;
  limits.pitch_max = 1.2;
  limits.roll_max = 1.2;
  return limits;
}

/// A constant-speed (v = 0.5 m/s) minimum-time problem.
inline BoundaryValueProblem cruise(double x0, double y0, double h0, double x1, double y1,
                                   double h1) {
  BoundaryValueProblem p;
  p.start = {x0, y0, h0, 0.5, 0.0};
  p.goal = {x1, y1, h1, 0.5, 0.0};
  p.limits = looseLimits();
  return p;
}

/// Flat ground, 20 m x 20 m at 0.25 m.
inline terrain::ElevationMap flatMap() {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kFlat;
  options.rows = 80;
  options.cols = 80;
  return terrain::generateTerrain(options);
}

/// 004_... fig. 5: from (3, 10, 0), goals 5 m away at bearings -40..40 deg (9) and headings
/// -60..60 deg (5).
inline std::vector<BoundaryValueProblem> flatFan() {
  std::vector<BoundaryValueProblem> problems;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 5; ++j) {
      const double bearing = (-40.0 + 10.0 * i) * kDeg;
      const double heading = (-60.0 + 30.0 * j) * kDeg;
      problems.push_back(cruise(3.0, 10.0, 0.0, 3.0 + 5.0 * std::cos(bearing),
                                10.0 + 5.0 * std::sin(bearing), heading));
    }
  }
  return problems;
}

/// Rough terrain for the lattice: generated hills, 16 m x 12 m at 0.25 m.
inline terrain::ElevationMap roughMap() {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kHills;
  options.rows = 48;
  options.cols = 64;
  options.cell = 0.25;
  options.seed = 7;
  return terrain::generateTerrain(options);
}

/// 004_... fig. 4: 35 nodes (7 columns 2 m apart x 5 rows 0.75 m apart, heading 0) and 94
/// edges drawn with seed 4 from the 114 forward edges (next column, row change <= 2).
inline std::vector<BoundaryValueProblem> roughLattice() {
  std::vector<BoundaryValueProblem> candidates;
  for (int i = 0; i + 1 < 7; ++i) {
    for (int j = 0; j < 5; ++j) {
      for (int k = 0; k < 5; ++k) {
        if (std::abs(k - j) > 2) continue;
        candidates.push_back(
            cruise(2.0 + 2.0 * i, 4.5 + 0.75 * j, 0.0, 2.0 + 2.0 * (i + 1), 4.5 + 0.75 * k, 0.0));
      }
    }
  }
  std::mt19937 random(4);
  std::shuffle(candidates.begin(), candidates.end(), random);
  candidates.resize(94);
  return candidates;
}

/// 004_... figs. 6-7: flat ground with one hill (height 0.6 m, sigma 0.7 m) centred 0.35 m
/// left of the line from (2, 5) to the goal 4 m ahead.
inline terrain::ElevationMap singleHillMap() {
  terrain::GridGeometry geometry;
  geometry.rows = 40;
  geometry.cols = 40;
  geometry.cell = 0.25;
  terrain::ElevationMap map(geometry);
  for (int r = 0; r < geometry.rows; ++r) {
    for (int c = 0; c < geometry.cols; ++c) {
      const double x = (c + 0.5) * geometry.cell, y = (r + 0.5) * geometry.cell;
      const double d2 = (x - 4.0) * (x - 4.0) + (y - 5.35) * (y - 5.35);
      map.elevation()(r, c) = static_cast<float>(0.6 * std::exp(-d2 / (2.0 * 0.7 * 0.7)));
    }
  }
  return map;
}

/// The slope-dwell problem: relative goal (4, 0, 0) at constant speed.
inline BoundaryValueProblem singleHillProblem(double alpha) {
  BoundaryValueProblem p = cruise(2.0, 5.0, 0.0, 6.0, 5.0, 0.0);
  p.cost = {alpha > 0.0 ? CostKind::kSlopeDwell : CostKind::kTime, alpha};
  return p;
}

}  // namespace terratraj::ocp::fixtures
