#include "terratraj/search/lattice_graph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "terratraj/search/goal_region.hpp"
#include "terratraj/search/primitive_generator.hpp"

namespace terratraj::search {
namespace {

constexpr double kStartHeadingTolerance = 1e-6;  // [rad]
constexpr int kDenseStepsPerCell = 8;            // footprint: curve points every cell / 8

// Linear interpolation of a primitive's samples at arc length s.
PrimitiveSample sampleAt(const MotionPrimitive& p, double s, std::size_t& hint) {
  const auto& q = p.samples;
  while (hint + 2 < q.size() && q[hint + 1].s < s) ++hint;
  const PrimitiveSample& a = q[hint];
  const PrimitiveSample& b = q[hint + 1];
  const double span = b.s - a.s;
  const double w = span > 0.0 ? std::clamp((s - a.s) / span, 0.0, 1.0) : 0.0;
  PrimitiveSample r;
  r.s = s;
  r.t = a.t + w * (b.t - a.t);
  r.x = a.x + w * (b.x - a.x);
  r.y = a.y + w * (b.y - a.y);
  r.heading = a.heading + w * (b.heading - a.heading);
  r.curvature = a.curvature + w * (b.curvature - a.curvature);
  return r;
}

}  // namespace

const char* edgeStatusName(EdgeStatus status) {
  switch (status) {
    case EdgeStatus::kValid:
      return "valid";
    case EdgeStatus::kOffMap:
      return "off_map";
    case EdgeStatus::kLethal:
      return "lethal";
    case EdgeStatus::kAttitude:
      return "attitude";
    case EdgeStatus::kPitch:
      return "pitch";
    case EdgeStatus::kRoll:
      return "roll";
    case EdgeStatus::kStall:
      return "stall";
  }
  return "unknown";
}

LatticeGraph::LatticeGraph(const PlanningProblem& problem, const PrimitiveSet& primitives,
                           const LatticeGraphOptions& options)
    : problem_(&problem), primitives_(&primitives), options_(options) {
  const terrain::GridGeometry& geometry = problem.map->geometry();
  const LatticeSpec& lattice = primitives.lattice;
  if (const std::optional<std::string> e = primitives.checkAgainst(lattice, &problem.limits)) {
    error_ = "motion primitives: " + *e;
    return;
  }
  if (!(options.slope_dwell_alpha >= 0.0) || !std::isfinite(options.slope_dwell_alpha)) {
    error_ = "slope_dwell_alpha: must be a finite number >= 0";
    return;
  }
  sample_spacing_ = options.sample_spacing > 0.0 ? options.sample_spacing : 0.5 * geometry.cell;
  const double ratio = lattice.resolution / geometry.cell;
  cells_per_node_ = std::abs(ratio - std::round(ratio)) < 1e-9 * ratio && std::round(ratio) >= 1
                        ? static_cast<int>(std::round(ratio))
                        : 0;
  origin_ = problem.start.position;
  const double res = lattice.resolution;
  i_min_ = static_cast<int>(std::ceil((0.0 - origin_.x()) / res));
  i_max_ = static_cast<int>(std::floor((geometry.width() - origin_.x()) / res));
  j_min_ = static_cast<int>(std::ceil((0.0 - origin_.y()) / res));
  j_max_ = static_cast<int>(std::floor((geometry.height() - origin_.y()) / res));
  const double nodes = static_cast<double>(i_max_ - i_min_ + 1) * (j_max_ - j_min_ + 1) *
                       (lattice.heading_count + 1);
  if (nodes >= static_cast<double>(std::uint64_t{1} << 42)) {
    error_ = "lattice: too many states (increase resolution_m)";
    return;
  }
  if (std::abs(problem.start.curvature) > 1e-9) {
    error_ = "start: the lattice planners start with zero curvature (omega = 0)";
    return;
  }
  templates_.resize(lattice.heading_count);
  for (int k = 0; k < lattice.heading_count; ++k) {
    for (const MotionPrimitive& p : primitives.by_heading[k])
      templates_[k].push_back(makeTemplate(p));
  }
  // The start: a lattice heading, or connectors from the exact heading.
  const int nearest = lattice.nearestHeading(problem.start.heading);
  const double gap = std::abs(wrapAngle(problem.start.heading - lattice.headingAngle(nearest)));
  if (gap <= kStartHeadingTolerance) {
    start_ = {0, 0, nearest};
    return;
  }
  start_ = {0, 0, kStartHeading};
  for (const MotionPrimitive& p : primitives.by_heading[nearest]) {
    std::optional<MotionPrimitive> c = solvePrimitive(
        problem.start.heading, p.offset.cast<double>() * res, lattice.headingAngle(p.end_heading),
        primitives.generation.speed, problem.limits, primitives.sample_spacing);
    if (!c) continue;
    c->start_heading = kStartHeading;
    c->end_heading = p.end_heading;
    c->offset = p.offset;
    connector_templates_.push_back(makeTemplate(*c));
    connectors_.push_back(std::move(*c));
  }
  if (connectors_.empty()) {
    error_ = "start.heading: no connector from the start heading to the lattice converged";
  }
}

LatticeGraph::EdgeTemplate LatticeGraph::makeTemplate(const MotionPrimitive& p) const {
  EdgeTemplate t;
  const terrain::GridGeometry& geometry = problem_->map->geometry();
  const double cell = geometry.cell;
  // Search samples every sample_spacing (at least one segment).
  const int n = std::max(1, static_cast<int>(std::ceil(p.length / sample_spacing_ - 1e-9)));
  std::size_t hint = 0;
  std::size_t rate_index = 1;
  double previous_s = 0.0;
  std::vector<double> rates(n + 1, 0.0);
  for (int k = 0; k <= n; ++k) {
    const double s = p.length * k / n;
    const PrimitiveSample q = sampleAt(p, s, hint);
    SearchSample sample;
    sample.offset = {q.x, q.y};
    sample.heading = q.heading;
    sample.curvature = q.curvature;
    sample.ds = 0.0;
    if (k > 0) {
      const SearchSample& prev = t.samples.back();
      sample.ds = (sample.offset - prev.offset).norm();
      // Largest |d kappa / ds| of the stored segments between the two samples, and of the
      // search segment itself.
      double rate = std::abs(q.curvature - prev.curvature) / std::max(s - previous_s, 1e-12);
      while (rate_index < p.samples.size() && p.samples[rate_index - 1].s < s) {
        const PrimitiveSample& a = p.samples[rate_index - 1];
        const PrimitiveSample& b = p.samples[rate_index];
        rate = std::max(rate, std::abs(b.curvature - a.curvature) / std::max(b.s - a.s, 1e-12));
        if (b.s >= s) break;
        ++rate_index;
      }
      rates[k - 1] = std::max(rates[k - 1], rate);
      rates[k] = std::max(rates[k], rate);
    }
    previous_s = s;
    t.samples.push_back(sample);
  }
  for (int k = 0; k <= n; ++k) {
    t.samples[k].rate_cap = rates[k] > 0.0 ? problem_->limits.sigma_max / rates[k]
                                           : std::numeric_limits<double>::infinity();
  }
  // Footprint: points every cell / 8 along the curve, each with the square of half-side
  // cell / 16 around it: the squares cover the curve, so every cell it touches is listed (and a
  // few it only nearly touches).
  const int m = std::max(1, static_cast<int>(std::ceil(p.length * kDenseStepsPerCell / cell)));
  const double half = cell / (2.0 * kDenseStepsPerCell) * (1.0 + 1e-6);
  hint = 0;
  std::set<std::pair<int, int>> cells;
  for (int k = 0; k <= m; ++k) {
    const PrimitiveSample q = sampleAt(p, p.length * k / m, hint);
    for (double dx : {-half, half}) {
      for (double dy : {-half, half}) {
        const Eigen::Vector2d d(q.x + dx, q.y + dy);
        if (cells_per_node_ > 0) {
          cells.insert({static_cast<int>(std::floor((origin_.x() + d.x()) / cell)),
                        static_cast<int>(std::floor((origin_.y() + d.y()) / cell))});
        } else {
          t.dense.push_back(d);
        }
      }
    }
  }
  for (const auto& [col, row] : cells) t.cells.emplace_back(col, row);
  return t;
}

std::uint64_t LatticeGraph::key(const LatticeState& s) const {
  const std::uint64_t headings = static_cast<std::uint64_t>(lattice().heading_count) + 1;
  const std::uint64_t width = static_cast<std::uint64_t>(j_max_ - j_min_ + 1);
  const std::uint64_t cell =
      static_cast<std::uint64_t>(s.i - i_min_) * width + static_cast<std::uint64_t>(s.j - j_min_);
  return cell * headings + static_cast<std::uint64_t>(s.heading + 1);
}

bool LatticeGraph::onLattice(const LatticeState& s) const {
  return s.i >= i_min_ && s.i <= i_max_ && s.j >= j_min_ && s.j <= j_max_;
}

Eigen::Vector2d LatticeGraph::position(const LatticeState& s) const {
  return origin_ + lattice().resolution * Eigen::Vector2d(s.i, s.j);
}

double LatticeGraph::heading(const LatticeState& s) const {
  return s.heading == kStartHeading ? problem_->start.heading : lattice().headingAngle(s.heading);
}

bool LatticeGraph::inGoal(const LatticeState& s) const {
  // The speed profile brakes to the goal's speed, so only position and heading matter here.
  PlannerState state;
  state.position = position(s);
  state.heading = heading(s);
  state.v = problem_->goal.v;
  return problem_->goal.contains(state);
}

double LatticeGraph::heuristic(const LatticeState& s) const {
  const GoalRegion& goal = problem_->goal;
  const double distance = (position(s) - goal.position).norm() - goal.position_tolerance;
  return std::max(0.0, distance) / problem_->limits.v_max;
}

int LatticeGraph::edgeCount(const LatticeState& s) const {
  if (s.heading == kStartHeading) return static_cast<int>(connectors_.size());
  return static_cast<int>(primitives_->by_heading[s.heading].size());
}

const MotionPrimitive& LatticeGraph::primitive(const LatticeState& s, int e) const {
  return s.heading == kStartHeading ? connectors_[e] : primitives_->by_heading[s.heading][e];
}

const LatticeGraph::EdgeTemplate& LatticeGraph::edgeTemplate(const LatticeState& s, int e) const {
  return s.heading == kStartHeading ? connector_templates_[e] : templates_[s.heading][e];
}

LatticeState LatticeGraph::target(const LatticeState& s, int e) const {
  const MotionPrimitive& p = primitive(s, e);
  return {s.i + p.offset.x(), s.j + p.offset.y(), p.end_heading};
}

double LatticeGraph::cap(const SearchSample& sample, double pitch, double roll) const {
  const models::VehicleLimits& l = problem_->limits;
  double c = std::min(l.v_max, sample.rate_cap);
  if (sample.curvature != 0.0) c = std::min(c, l.omega_max / std::abs(sample.curvature));
  if (problem_->pitch_table != nullptr) c = std::min(c, problem_->pitch_table->lookup(pitch));
  if (problem_->roll_curvature_table != nullptr) {
    c = std::min(c, problem_->roll_curvature_table->lookup(roll, sample.curvature));
  }
  return c;
}

EdgeEvaluation LatticeGraph::evaluate(const LatticeState& s, int e) const {
  EdgeEvaluation out;
  const auto fail = [&out](EdgeStatus status) {
    out.status = status;
    out.cost = out.time = std::numeric_limits<double>::infinity();
    return out;
  };
  if (!onLattice(s) || !onLattice(target(s, e))) return fail(EdgeStatus::kOffMap);
  const EdgeTemplate& t = edgeTemplate(s, e);
  const terrain::ElevationMap& map = *problem_->map;
  const terrain::GridGeometry& geometry = map.geometry();
  const Eigen::Vector2d p0 = position(s);
  if (cells_per_node_ > 0) {
    const int dc = cells_per_node_ * s.i, dr = cells_per_node_ * s.j;
    for (const Eigen::Vector2i& c : t.cells) {
      const terrain::CellIndex cell{c.y() + dr, c.x() + dc};
      if (!geometry.isValid(cell)) return fail(EdgeStatus::kOffMap);
      if (map.isLethal(cell) || map.isNoData(cell)) return fail(EdgeStatus::kLethal);
    }
  } else {
    for (const Eigen::Vector2d& d : t.dense) {
      const std::optional<terrain::CellIndex> cell = geometry.cellAt(p0 + d);
      if (!cell) return fail(EdgeStatus::kOffMap);
      if (map.isLethal(*cell) || map.isNoData(*cell)) return fail(EdgeStatus::kLethal);
    }
  }
  const models::VehicleLimits& l = problem_->limits;
  const double alpha = options_.slope_dwell_alpha;
  workspace_.has_warm_start = false;
  double previous_cap = 0.0, previous_z = 0.0, previous_dwell = 0.0;
  for (std::size_t k = 0; k < t.samples.size(); ++k) {
    const SearchSample& sample = t.samples[k];
    const Eigen::Vector2d p = p0 + sample.offset;
    const models::AttitudeStatus status =
        problem_->vehicle->compute({p.x(), p.y(), sample.heading}, workspace_, attitude_);
    if (status != models::AttitudeStatus::kOk) {
      return fail(status == models::AttitudeStatus::kNoTerrain ? EdgeStatus::kOffMap
                                                               : EdgeStatus::kAttitude);
    }
    const models::Attitude& a = attitude_.attitude;
    if (std::abs(a.pitch) > l.pitch_max) return fail(EdgeStatus::kPitch);
    if (std::abs(a.roll) > l.roll_max) return fail(EdgeStatus::kRoll);
    const double c = cap(sample, a.pitch, a.roll);
    if (c < kMinCapSpeed) return fail(EdgeStatus::kStall);
    const double dwell = a.roll * a.roll + a.pitch * a.pitch;
    if (k > 0) {
      const double dz = a.z - previous_z;
      const double ds = std::sqrt(sample.ds * sample.ds + dz * dz);
      const double dt = 2.0 * ds / (c + previous_cap);
      out.time += dt;
      out.cost += dt * (1.0 + alpha * 0.5 * (dwell + previous_dwell));
    }
    previous_cap = c;
    previous_z = a.z;
    previous_dwell = dwell;
  }
  return out;
}

void LatticeGraph::edgePoints(const LatticeState& s, int e,
                              std::vector<Eigen::Vector2d>& out) const {
  const EdgeTemplate& t = edgeTemplate(s, e);
  const Eigen::Vector2d p0 = position(s);
  out.clear();
  for (const SearchSample& sample : t.samples) out.push_back(p0 + sample.offset);
}

Expected<LatticeTrajectory> LatticeGraph::trajectory(const std::vector<LatticeStep>& path) const {
  const auto fail = [](std::string why) { return unexpected(std::move(why)); };
  if (path.empty()) return fail("empty path");
  LatticeTrajectory out;
  models::Trajectory& trajectory = out.trajectory;
  std::vector<double> lengths, caps;
  std::vector<models::TrajectorySample>& samples = trajectory.samples;
  for (std::size_t step = 0; step < path.size(); ++step) {
    const LatticeState& s = path[step].from;
    const int e = path[step].edge;
    if (step > 0 && !(target(path[step - 1].from, path[step - 1].edge) == s)) {
      return fail("path steps do not chain at step " + std::to_string(step));
    }
    const EdgeEvaluation evaluation = evaluate(s, e);
    if (evaluation.status != EdgeStatus::kValid) {
      return fail("step " + std::to_string(step) + ": edge " + edgeStatusName(evaluation.status));
    }
    out.cost += evaluation.cost;
    const EdgeTemplate& t = edgeTemplate(s, e);
    const Eigen::Vector2d p0 = position(s);
    workspace_.has_warm_start = false;
    if (step > 0) {  // the junction sample is the previous edge's last: add this edge's cap
      caps.back() =
          std::min(caps.back(), cap(t.samples.front(), samples.back().pitch, samples.back().roll));
    }
    for (std::size_t k = step == 0 ? 0 : 1; k < t.samples.size(); ++k) {
      const SearchSample& sample = t.samples[k];
      const Eigen::Vector2d p = p0 + sample.offset;
      problem_->vehicle->compute({p.x(), p.y(), sample.heading}, workspace_, attitude_);
      models::TrajectorySample row{};
      row.x = p.x();
      row.y = p.y();
      row.z = attitude_.attitude.z;
      row.heading = wrapAngle(sample.heading);
      row.roll = attitude_.attitude.roll;
      row.pitch = attitude_.attitude.pitch;
      row.curvature = sample.curvature;
      caps.push_back(cap(sample, row.pitch, row.roll));
      if (!samples.empty()) {
        const models::TrajectorySample& prev = samples.back();
        const double dz = row.z - prev.z;
        lengths.push_back(std::sqrt(sample.ds * sample.ds + dz * dz));
        out.length += sample.ds;
      }
      samples.push_back(row);
    }
  }
  const SpeedProfileStatus status =
      profile_.compute(lengths, caps, problem_->start.v, problem_->goal.v, problem_->limits.a_max);
  if (status != SpeedProfileStatus::kOk) {
    return fail(std::string("speed profile: ") + speedProfileStatusName(status));
  }
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k].t = profile_.times()[k];
    samples[k].v = profile_.speeds()[k];
    samples[k].omega = samples[k].v * samples[k].curvature;
  }
  trajectory.has_column.fill(true);
  out.duration = profile_.duration();
  return out;
}

}  // namespace terratraj::search
