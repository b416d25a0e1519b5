// CandidateRefiner's geometry of a candidate: the corridor around it (a map whose cells outside
// it are lethal, for the corridor retry) and its shortcut path (for wiggly candidates).

#include <algorithm>
#include <cmath>
#include <vector>

#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::refine {
namespace {

// Shortcutting: the candidate is resampled this often [m] and a straight segment may skip at
// most this many samples.
constexpr double kShortcutSpacing = 0.5;
constexpr std::size_t kShortcutWindow = 200;

}  // namespace

terrain::ElevationMap CandidateRefiner::corridorMap(const models::Trajectory& candidate) const {
  terrain::ElevationMap map = *problem_->map;
  const terrain::GridGeometry& g = map.geometry();
  terrain::GridLayer& lethal = map.addLayer(terrain::layer_names::kLethal, 0.0f);
  std::vector<unsigned char> inside(g.cellCount(), 0);
  const double radius = options_.corridor_radius_m;
  const int reach = static_cast<int>(std::ceil(radius / g.cell));
  const auto markDisc = [&](const Eigen::Vector2d& centre) {
    const std::optional<terrain::CellIndex> c = g.cellAt(centre);
    if (!c) return;
    for (int r = std::max(0, c->row - reach); r <= std::min(g.rows - 1, c->row + reach); ++r) {
      for (int k = std::max(0, c->col - reach); k <= std::min(g.cols - 1, c->col + reach); ++k) {
        if ((g.cellCenter({r, k}) - centre).norm() <= radius) {
          inside[g.linearIndex({r, k})] = 1;
        }
      }
    }
  };
  // Discs every half cell along the candidate: their union is the corridor.
  const std::vector<models::TrajectorySample>& s = candidate.samples;
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const Eigen::Vector2d a(s[i].x, s[i].y), b(s[i + 1].x, s[i + 1].y);
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * g.cell))));
    for (int j = 0; j <= steps; ++j) markDisc(a + (b - a) * (static_cast<double>(j) / steps));
  }
  for (int r = 0; r < g.rows; ++r) {
    for (int k = 0; k < g.cols; ++k) {
      if (!inside[g.linearIndex({r, k})]) lethal(r, k) = 1.0f;
    }
  }
  return map;
}

std::vector<Eigen::Vector2d> CandidateRefiner::shortcutPath(
    const std::vector<Eigen::Vector2d>& path, double clearance) const {
  // The path every half metre.
  std::vector<Eigen::Vector2d> points{path.front()};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d a = path[i - 1], b = path[i];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kShortcutSpacing)));
    for (int j = 1; j <= steps; ++j)
      points.push_back(a + (b - a) * (static_cast<double>(j) / steps));
  }
  const double step = 0.25 * problem_->map->geometry().cell;
  models::AttitudeWorkspace workspace;
  models::AttitudeResult placed;
  // Clear of impassable cells by `clearance`, then (the costlier test, for the segments that
  // pass the first) the vehicle can be placed along it, within its pitch and roll limits: beside
  // no data the surface is undefined farther out than the no-data cells themselves on a coarse
  // map, and a straight cut across a slope the candidate went round leaves the optimiser an
  // infeasible start it may not recover from (moon DEM: a 57 m PRM route, shortcut across the
  // slopes, refined to a 368 m wander). Likewise where the speed tables leave less than a tenth
  // of v_max (the Segway's look-ups forbid slopes beyond 20 deg along the heading, within its
  // pitch limit: on davosdorf a PRM route cut straight across them started the Segway's
  // collocation 2 m/s beyond its slope bound, and it wandered for 1,000 iterations).
  const models::VehicleLimits& limits = problem_->limits;
  const auto clear = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int j = 0; j <= steps; ++j) {
      const std::optional<terrain::Clearance> c =
          clearance_.at(a + (b - a) * (static_cast<double>(j) / steps));
      if (!c || c->distance < clearance) return false;
    }
    const double heading = std::atan2(b.y() - a.y(), b.x() - a.x());
    for (int j = 0; j <= steps; ++j) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(j) / steps);
      if (problem_->vehicle->compute({p.x(), p.y(), heading}, workspace, placed) !=
              models::AttitudeStatus::kOk ||
          std::abs(placed.attitude.pitch) > limits.pitch_max ||
          std::abs(placed.attitude.roll) > limits.roll_max ||
          bvp_->tables.speedCap(placed.attitude, 0.0, limits.v_max) < 0.1 * limits.v_max) {
        return false;
      }
    }
    return true;
  };
  // Greedy: from each kept point, the farthest point within the window reachable straight.
  std::vector<Eigen::Vector2d> out{points.front()};
  std::size_t i = 0;
  const std::size_t last = points.size() - 1;
  while (i < last) {
    std::size_t best = i + 1;
    for (std::size_t j = std::min(last, i + kShortcutWindow); j > i + 1; --j) {
      if (clear(points[i], points[j])) {
        best = j;
        break;
      }
    }
    out.push_back(points[best]);
    i = best;
  }
  return out;
}

}  // namespace terratraj::refine
