#include "terratraj/search/primitive_generator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>
#include <tuple>

#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/flat_ground_model.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::search {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;

// A surface that only stands behind the flat-ground model (never sampled).
struct FlatWorld {
  FlatWorld()
      : map([] {
          terrain::GridGeometry g;
          g.rows = g.cols = 2;
          g.cell = 1.0;
          return g;
        }()),
        surface(map, terrain::Interpolation::kBilinear),
        model(surface) {}
  terrain::ElevationMap map;
  terrain::TerrainSurface surface;
  ocp::FlatGroundModel model;
};

// Shortest symmetric turn by |dtheta| [rad] with |dkappa/ds| <= sigma_s and |kappa| <= kappa_max:
// two clothoids, with a circular arc between them when the curvature bound is reached [m].
double minimumTurnLength(double dtheta, double sigma_s, double kappa_max) {
  dtheta = std::abs(dtheta);
  const double kappa_peak = std::sqrt(dtheta * sigma_s);
  if (kappa_peak <= kappa_max) return 2.0 * kappa_peak / sigma_s;
  return 2.0 * kappa_max / sigma_s + (dtheta - kappa_max * kappa_max / sigma_s) / kappa_max;
}

// Samples of a trajectory resampled every `spacing` metres of planar arc length.
std::vector<PrimitiveSample> resample(const models::Trajectory& trajectory, double spacing) {
  const auto& in = trajectory.samples;
  std::vector<double> s(in.size(), 0.0);
  for (std::size_t i = 1; i < in.size(); ++i) {
    s[i] = s[i - 1] + std::hypot(in[i].x - in[i - 1].x, in[i].y - in[i - 1].y);
  }
  const double length = s.back();
  const int n = std::max(1, static_cast<int>(std::ceil(length / spacing - 1e-9)));
  std::vector<PrimitiveSample> out;
  out.reserve(n + 1);
  std::size_t seg = 0;
  for (int k = 0; k <= n; ++k) {
    const double target = length * k / n;
    while (seg + 2 < in.size() && s[seg + 1] < target) ++seg;
    const double span = s[seg + 1] - s[seg];
    const double w = span > 0.0 ? std::clamp((target - s[seg]) / span, 0.0, 1.0) : 0.0;
    const auto lerp = [w](double a, double b) { return a + w * (b - a); };
    const models::TrajectorySample& a = in[seg];
    const models::TrajectorySample& b = in[seg + 1];
    PrimitiveSample p;
    p.s = target;
    p.t = lerp(a.t, b.t);
    p.x = lerp(a.x, b.x);
    p.y = lerp(a.y, b.y);
    p.heading = lerp(a.heading, b.heading);
    p.curvature = lerp(a.curvature, b.curvature);
    out.push_back(p);
  }
  return out;
}

void finalise(MotionPrimitive& p) {
  p.length = p.samples.back().s;
  p.duration = p.samples.back().t;
  p.max_abs_curvature = 0.0;
  p.max_abs_curvature_rate = 0.0;
  for (std::size_t i = 0; i < p.samples.size(); ++i) {
    p.max_abs_curvature = std::max(p.max_abs_curvature, std::abs(p.samples[i].curvature));
    if (i > 0) {
      const double ds = p.samples[i].s - p.samples[i - 1].s;
      p.max_abs_curvature_rate =
          std::max(p.max_abs_curvature_rate,
                   std::abs(p.samples[i].curvature - p.samples[i - 1].curvature) / ds);
    }
  }
}

// Lattice offsets to try for a turn by dtheta from `heading`, best first, at most `count`:
// chords at least as long as the reference turn and at most 3 times, whose direction deviates
// from the turn's mean heading by an angle an S-bend of that length can absorb (lateral offset
// sigma_s L^3 / 32 for four clothoids of length L / 4, halved for safety; or kappa_max L^2 / 4
// for two arcs, where that is less: with a large sigma_s, kappa_max binds), shortest first.
std::vector<Eigen::Vector2i> candidateOffsets(double heading, double dtheta, double reference,
                                              double sigma_s, double kappa_max, double resolution,
                                              int count) {
  const double half = 0.5 * dtheta;
  const double chord_min =
      std::abs(half) > 1e-12 ? reference * std::sin(std::abs(half)) / std::abs(half) : reference;
  const double chord_max = 3.0 * std::max(chord_min, resolution);
  const double direction = heading + half;
  const int reach = static_cast<int>(std::ceil(chord_max / resolution));
  std::vector<std::pair<double, Eigen::Vector2i>> scored;
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      const Eigen::Vector2d chord = Eigen::Vector2d(dx, dy) * resolution;
      const double length = chord.norm();
      if (length < chord_min - 1e-9 || length > chord_max || length == 0.0) continue;
      const double deviation =
          std::abs(std::remainder(std::atan2(chord.y(), chord.x()) - direction, kTwoPi));
      if (deviation > 0.25 * kTwoPi) continue;
      const double s_bend = length - (reference - chord_min);  // length left after the turn
      // Four clothoids reach sigma_s L^3 / 32 sideways; with |kappa| <= kappa_max (what binds
      // when sigma_s is large) two arcs reach about kappa_max L^2 / 4.
      const double tolerance =
          std::min(0.5 * sigma_s * s_bend * s_bend / 32.0, kappa_max * s_bend / 4.0);
      if (deviation > tolerance + 1e-12) continue;
      scored.emplace_back(length + 0.01 * deviation, Eigen::Vector2i(dx, dy));
    }
  }
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) {
    return a.first < b.first ||
           (a.first == b.first && std::make_pair(a.second.x(), a.second.y()) <
                                      std::make_pair(b.second.x(), b.second.y()));
  });
  std::vector<Eigen::Vector2i> out;
  for (const auto& candidate : scored) {
    if (static_cast<int>(out.size()) >= count) break;
    out.push_back(candidate.second);
  }
  return out;
}

MotionPrimitive rotateQuarterTurns(const MotionPrimitive& p, int quarter_turns,
                                   const LatticeSpec& lattice) {
  const int shift = quarter_turns * lattice.heading_count / 4;
  const double angle = quarter_turns * kTwoPi / 4.0;
  const double c = std::round(std::cos(angle)), s = std::round(std::sin(angle));
  MotionPrimitive r = p;
  r.start_heading = lattice.wrapHeading(p.start_heading + shift);
  r.end_heading = lattice.wrapHeading(p.end_heading + shift);
  r.offset =
      Eigen::Vector2i(static_cast<int>(c) * p.offset.x() - static_cast<int>(s) * p.offset.y(),
                      static_cast<int>(s) * p.offset.x() + static_cast<int>(c) * p.offset.y());
  for (PrimitiveSample& q : r.samples) {
    const double x = q.x, y = q.y;
    q.x = c * x - s * y;
    q.y = s * x + c * y;
    q.heading += angle;
  }
  return r;
}

// solvePrimitive() with the limits as given.
std::optional<MotionPrimitive> solveOnce(double start_heading, const Eigen::Vector2d& end,
                                         double end_heading, double speed,
                                         const models::VehicleLimits& limits, double sample_spacing,
                                         int max_iterations) {
  static thread_local FlatWorld world;
  if (!(speed > 0.0) || !std::isfinite(speed)) return std::nullopt;
  // A constant-speed primitive's path depends on the speed only through the bounds per arc
  // length (kappa <= omega_max / v, dkappa/ds <= sigma_max / v): it is solved at 1 m/s with
  // those bounds, and its times are scaled by 1 / speed. The solver's scaling then does not
  // depend on the speed (at 0.01 m/s its final time would be a hundred times longer).
  ocp::BoundaryValueProblem problem;
  problem.start = {0.0, 0.0, start_heading, 1.0, 0.0};
  // Unwrap the goal heading to the turn nearest the straight line's.
  const double turn = std::remainder(end_heading - start_heading, kTwoPi);
  problem.goal = {end.x(), end.y(), start_heading + turn, 1.0, 0.0};
  problem.cost.kind = ocp::CostKind::kTime;
  problem.limits = limits;
  problem.limits.v_max = 1.0 + 1e-9;
  problem.limits.omega_max = limits.omega_max / speed;
  problem.limits.sigma_max = limits.sigma_max / speed;
  problem.limits.a_max = std::max(limits.a_max / speed, 1.0);
  if (ocp::validateProblem(problem)) return std::nullopt;
  ocp::BoundaryValueOptions options;
  options.method = ocp::BoundaryValueMethod::kIpopt;  // enforces sigma_max, kappa_max
  options.max_iterations = max_iterations;
  options.verification.sample_dt = std::min(0.01, 0.25 * sample_spacing);
  const ocp::BoundaryValueSolution solution =
      ocp::solveBoundaryValue(world.model, problem, options, nullptr);
  if (solution.status != ocp::SolveStatus::kConverged || !solution.verified.ok ||
      solution.verified.trajectory.samples.size() < 2) {
    return std::nullopt;
  }
  MotionPrimitive p;
  p.samples = resample(solution.verified.trajectory, sample_spacing);
  for (PrimitiveSample& q : p.samples) q.t /= speed;
  // Snap: spread the solver's terminal error (< 1 mm) along the arc so the end is exact.
  const PrimitiveSample last = p.samples.back();
  const double length = last.s;
  const Eigen::Vector2d error(end.x() - last.x, end.y() - last.y);
  const double heading_error = problem.goal.heading - last.heading;
  for (PrimitiveSample& q : p.samples) {
    const double w = q.s / length;
    q.x += w * error.x();
    q.y += w * error.y();
    q.heading += w * heading_error;
  }
  p.samples.front().x = p.samples.front().y = 0.0;
  p.samples.front().heading = start_heading;
  p.samples.front().curvature = p.samples.back().curvature = 0.0;
  finalise(p);
  return p;
}

}  // namespace

std::optional<MotionPrimitive> solvePrimitive(double start_heading, const Eigen::Vector2d& end,
                                              double end_heading, double speed,
                                              const models::VehicleLimits& limits,
                                              double sample_spacing, int max_iterations) {
  // The solver holds kappa_max at its constraint points; between them the curvature can pass
  // it by a few 1e-4 where it turns sharply (a large sigma_max: 20 1/(m s) passed it by 4.5e-4,
  // which the primitive set's check refuses). Solved again with kappa_max lowered by what
  // passed, so a primitive never breaks the limit it is checked against.
  models::VehicleLimits tightened = limits;
  for (int attempt = 0; attempt < 3; ++attempt) {
    std::optional<MotionPrimitive> p = solveOnce(start_heading, end, end_heading, speed, tightened,
                                                 sample_spacing, max_iterations);
    if (!p || p->max_abs_curvature <= limits.kappa_max * (1.0 + 1e-6)) return p;
    tightened.kappa_max *= (limits.kappa_max / p->max_abs_curvature) * (1.0 - 1e-3);
  }
  return std::nullopt;
}

PrimitiveGenerationResult generatePrimitives(const LatticeSpec& lattice,
                                             const models::VehicleLimits& limits,
                                             const PrimitiveGenerationOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  PrimitiveGenerationResult result;
  PrimitiveSet& set = result.set;
  set.lattice = lattice;
  set.sample_spacing = options.sample_spacing;
  const double speed = options.speed > 0.0 ? options.speed : limits.v_max;
  set.generation.speed = speed;
  set.generation.kappa_max = limits.kappa_max;
  set.generation.sigma_max = limits.sigma_max;
  set.generation.omega_max = limits.omega_max;
  set.generation.turns = options.turns;
  set.by_heading.assign(lattice.heading_count, {});
  if (lattice.validate()) {
    result.failures.push_back("lattice: " + *lattice.validate());
    return result;
  }
  // Curvature bound: kappa_max, and omega_max at the generation speed.
  const double kappa_max = std::min(limits.kappa_max, limits.omega_max / speed);
  const double sigma_s = limits.sigma_max / speed;  // |dkappa/ds| bound [1/m^2]
  const bool symmetric = lattice.heading_count % 4 == 0;
  const int solved_headings = symmetric ? lattice.heading_count / 4 : lattice.heading_count;

  // Requests: (turn, reference length); straight moves first.
  std::vector<std::pair<int, double>> requests;
  for (double length : options.straight_lengths) requests.emplace_back(0, length);
  for (int turn : options.turns) {
    if (turn == 0) continue;
    const double dtheta = kTwoPi * turn / lattice.heading_count;
    requests.emplace_back(turn,
                          options.length_margin * minimumTurnLength(dtheta, sigma_s, kappa_max));
  }

  for (int k = 0; k < solved_headings; ++k) {
    if (options.stop != nullptr && options.stop->load()) {
      result.failures.push_back("stopped (interrupt) before heading " + std::to_string(k));
      break;
    }
    if (options.progress) options.progress(k, solved_headings);
    const double heading = lattice.headingAngle(k);
    std::set<std::tuple<int, int, int>> seen;  // (end heading, dx, dy)
    for (const auto& [turn, reference] : requests) {
      const int end_index = lattice.wrapHeading(k + turn);
      const double dtheta = kTwoPi * turn / lattice.heading_count;
      // The offsets near the reference length first; when every one of them fails (a short
      // reference: a large sigma_max, where kappa_max binds), the reference 25 % longer, up to
      // `attempts` times, each offset solved once.
      bool found = false;
      std::set<std::pair<int, int>> tried;
      double length = reference;
      for (int growth = 0; growth < options.attempts && !found; ++growth, length *= 1.25) {
        for (const Eigen::Vector2i& offset :
             candidateOffsets(heading, dtheta, length, sigma_s, kappa_max, lattice.resolution,
                              options.attempts)) {
          if (seen.count({end_index, offset.x(), offset.y()})) {
            found = true;  // an earlier request already produced this primitive
            break;
          }
          if (!tried.insert({offset.x(), offset.y()}).second) continue;
          ++set.generation.solves;
          std::optional<MotionPrimitive> p = solvePrimitive(
              heading, offset.cast<double>() * lattice.resolution, lattice.headingAngle(end_index),
              speed, limits, options.sample_spacing, options.max_iterations);
          if (!p) {
            ++set.generation.failures;
            continue;
          }
          p->start_heading = k;
          p->end_heading = end_index;
          p->offset = offset;
          seen.insert({end_index, offset.x(), offset.y()});
          set.by_heading[k].push_back(std::move(*p));
          found = true;
          break;
        }
      }
      if (!found) {
        std::ostringstream text;
        text << "heading " << k << ", turn " << turn << ": no converged primitive in "
             << tried.size() << " offsets (" << options.attempts << " reference lengths)";
        result.failures.push_back(text.str());
      }
    }
  }
  if (symmetric) {
    for (int quarter = 1; quarter < 4; ++quarter) {
      for (int k = 0; k < solved_headings; ++k) {
        for (const MotionPrimitive& p : set.by_heading[k]) {
          MotionPrimitive r = rotateQuarterTurns(p, quarter, lattice);
          set.by_heading[r.start_heading].push_back(std::move(r));
        }
      }
    }
  }
  set.generation.generation_time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace terratraj::search
