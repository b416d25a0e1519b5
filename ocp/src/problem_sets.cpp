#include "terratraj/ocp/problem_sets.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::ocp::problem_sets {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

bool clearAround(const terrain::ElevationMap& map, double x, double y, double margin) {
  const terrain::GridGeometry& g = map.geometry();
  const int reach = static_cast<int>(std::ceil(margin / g.cell));
  const int col = static_cast<int>(std::floor(x / g.cell));
  const int row = static_cast<int>(std::floor(y / g.cell));
  for (int r = row - reach; r <= row + reach; ++r) {
    for (int c = col - reach; c <= col + reach; ++c) {
      if (r < 0 || c < 0 || r >= g.rows || c >= g.cols) return false;
      if (map.isNoData({r, c}) || map.isLethal({r, c})) return false;
    }
  }
  return true;
}

models::VehicleLimits looseLimits() {
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

BoundaryValueProblem cruise(double x0, double y0, double h0, double x1, double y1, double h1) {
  BoundaryValueProblem p;
  p.start = {x0, y0, h0, 0.5, 0.0};
  p.goal = {x1, y1, h1, 0.5, 0.0};
  p.limits = looseLimits();
  return p;
}

terrain::ElevationMap flatMap() {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kFlat;
  options.rows = 80;
  options.cols = 80;
  return terrain::generateTerrain(options);
}

std::vector<BoundaryValueProblem> flatFan() {
  std::vector<BoundaryValueProblem> problems;
  constexpr double kDeg = kPi / 180.0;
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

terrain::ElevationMap roughMap() {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kHills;
  options.rows = 48;
  options.cols = 64;
  options.cell = 0.25;
  options.seed = 7;
  return terrain::generateTerrain(options);
}

std::vector<BoundaryValueProblem> roughLattice() {
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

terrain::ElevationMap singleHillMap() {
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

BoundaryValueProblem singleHillProblem(double alpha) {
  BoundaryValueProblem p = cruise(2.0, 5.0, 0.0, 6.0, 5.0, 0.0);
  p.cost = {alpha > 0.0 ? CostKind::kSlopeDwell : CostKind::kTime, alpha};
  return p;
}

std::vector<BoundaryValueProblem> randomProblems(const terrain::ElevationMap& map,
                                                 const RandomProblemOptions& options) {
  if (options.count < 1) throw InputError("random problems: count must be >= 1");
  if (!(options.min_distance_m > 0.0 && options.max_distance_m >= options.min_distance_m)) {
    throw InputError("random problems: need 0 < min_distance_m <= max_distance_m");
  }
  const terrain::GridGeometry& g = map.geometry();
  const double width = g.cols * g.cell, height = g.rows * g.cell;
  std::mt19937_64 random(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BoundaryValueProblem> problems;
  const long attempts = 100L * options.count;
  for (long a = 0; a < attempts && static_cast<int>(problems.size()) < options.count; ++a) {
    const double x0 = width * unit(random), y0 = height * unit(random);
    const double bearing = 2.0 * kPi * unit(random);
    const double distance =
        options.min_distance_m + (options.max_distance_m - options.min_distance_m) * unit(random);
    const double x1 = x0 + distance * std::cos(bearing), y1 = y0 + distance * std::sin(bearing);
    const double h0 = bearing + options.max_heading_change * (2.0 * unit(random) - 1.0);
    const double h1 = bearing + options.max_heading_change * (2.0 * unit(random) - 1.0);
    if (!clearAround(map, x0, y0, options.edge_margin_m) ||
        !clearAround(map, x1, y1, options.edge_margin_m)) {
      continue;
    }
    problems.push_back(cruise(x0, y0, wrapAngle(h0), x1, y1, wrapAngle(h1)));
  }
  if (static_cast<int>(problems.size()) < options.count) {
    throw InputError("random problems: only " + std::to_string(problems.size()) + " of " +
                     std::to_string(options.count) + " fit on the map (margin " +
                     std::to_string(options.edge_margin_m) + " m)");
  }
  return problems;
}

}  // namespace terratraj::ocp::problem_sets
