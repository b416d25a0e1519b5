// CandidateRefiner's geometry of a candidate: the corridor around it (a map whose cells outside
// it are lethal, for the corridor retry), its shortcut path (for wiggly candidates), the guess
// the optimiser starts from, and the clearance row that keeps it off impassable cells.

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "polyline.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::refine {
namespace {

using detail::polyline;
using detail::polylineLength;

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
  // slopes, refined to a 368 m wander).
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
          std::abs(placed.attitude.roll) > limits.roll_max) {
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

bool CandidateRefiner::placeable(const ocp::TranscriptionGuess& guess, int samples) const {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult placed;
  const auto at = [&](const ocp::PointVector& w) {
    return problem_->vehicle->compute({w(0), w(1), w(2)}, workspace, placed) ==
           models::AttitudeStatus::kOk;
  };
  for (const ocp::PointVector& w : guess.points) {
    if (!at(w)) return false;
  }
  const double duration = guess.finalTime();
  for (int k = 1; k < samples && !guess.points.empty(); ++k) {
    if (!at(guess.at(duration * k / samples))) return false;
  }
  return true;
}

ocp::TranscriptionGuess CandidateRefiner::startingGuess(const TrajectoryFigures& before,
                                                        const ocp::TranscriptionGuess& candidate,
                                                        RefinementResult& out) const {
  ocp::TranscriptionGuess guess = candidate;
  // A wiggly candidate (a PRM's first solution, with loops) starts the optimiser from its
  // shortcut path instead, when that keeps the class: loops and detours cost iterations and
  // can trap it.
  if (options_.shortcut_clearance_m > 0.0) {
    const std::vector<Eigen::Vector2d> shortcut =
        shortcutPath(polyline(out.candidate), options_.shortcut_clearance_m);
    const double length = polylineLength(shortcut);
    if (length < options_.shortcut_gain * before.length_m && classOf(shortcut) == before.homotopy) {
      Expected<ocp::TranscriptionGuess> shorter =
          ocp::guessFromPath(shortcut, *bvp_, options_.guess_spacing_m);
      if (shorter && placeable(*shorter)) {
        guess = std::move(*shorter);
        out.guess_shortcut_m = before.length_m - length;
      }
    }
  }
  // A slow candidate whose shortcut is not used (a PRM's first solution on a forest: its path
  // near the shortest, its speed profile slow) starts from its own path re-timed by the
  // forward-backward speed pass when that is faster: an evenly sampled, consistent guess (the
  // PRM's own samples change speed at every milestone). Forest PRM first solutions: 54-142 ->
  // 19-68 coarse iterations, the same optima (bench refine).
  if (out.guess_shortcut_m == 0.0 && !(guess.finalTime() <= nearOptimalTime(before.length_m))) {
    if (Expected<ocp::TranscriptionGuess> retimed =
            ocp::guessFromPath(polyline(out.candidate), *bvp_, options_.guess_spacing_m)) {
      if (retimed->finalTime() < guess.finalTime() && placeable(*retimed)) {
        out.guess_retimed_s = guess.finalTime() - retimed->finalTime();
        guess = std::move(*retimed);
      }
    }
  }
  return guess;
}

void CandidateRefiner::holdClearance(const TrajectoryFigures& before,
                                     const terrain::ClearanceMap& clearance,
                                     ocp::TranscriptionSolveOptions& solve,
                                     RefinementResult& out) const {
  // The clearance constraint keeps the optimiser off impassable cells; a trajectory that clips
  // one between its points is solved again with at least half a cell of clearance (capped by
  // min_clearance_m): the bilinear distance transform rounds a lethal cell's corners.
  // Never above the clearance of the exact start and goal: a start beside no data (a coarse
  // map, where the surface is undefined a cell and a half out) or in a concave corner may have
  // none, or a little less than none, and the row would be infeasible there.
  if (!clearance_.hasImpassableCells()) return;
  const auto clearanceAt = [&](const ocp::VehicleState& s) {
    const std::optional<terrain::Clearance> c = clearance.at({s.x, s.y});
    return c ? c->distance : std::numeric_limits<double>::infinity();
  };
  const double ends = std::min(clearanceAt(bvp_->start), clearanceAt(bvp_->goal));
  const double lowest = std::min(before.min_clearance_m, ends);
  out.clearance_used_m = lowest > 0.0 ? std::min(options_.min_clearance_m, 0.5 * lowest) : lowest;
  solve.transcription.model.clearance = {&clearance, out.clearance_used_m};
  solve.clearance_floor = std::min(
      {options_.min_clearance_m, 0.5 * problem_->map->geometry().cell, std::max(ends, lowest)});
}

}  // namespace terratraj::refine
