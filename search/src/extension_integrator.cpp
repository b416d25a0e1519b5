#include "terratraj/search/extension_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "terratraj/terrain/no_data_band.hpp"
#include "terratraj/terrain/tangent_plane_patch.hpp"

namespace terratraj::search {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A turn toward a target never needs more than pi; beyond this the target is inside the
// turning circle.
constexpr double kMaxTurn = 1.5 * kPi;
// Simpson sub-intervals for the position along one clothoid step (even).
constexpr int kSimpsonIntervals = 4;
// Within this many steps of the target the steering only straightens.
constexpr double kFinalApproachSteps = 4.0;
// Lateral misses below this fraction of the end tolerance are not corrected.
constexpr double kLateralSlackFraction = 0.25;
// Slack beyond the vehicle's sampling radius within which the chords are checked near no data
// [m] (a chord whose ends lie farther out can still pass closer between them).
constexpr double kChordSlackM = 1.0;
// Chord checks every this fraction of a cell.
constexpr double kChordSpacingCells = 0.25;

// Position (u, w) and angle after arc length h in a plane, starting at the origin along +u with
// curvature varying linearly from k0 to k1.
void clothoidStep(double k0, double k1, double h, double& u, double& w, double& angle) {
  const double rate = (k1 - k0) / h;
  const auto angle_at = [&](double s) { return k0 * s + 0.5 * rate * s * s; };
  const double step = h / kSimpsonIntervals;
  double su = 0.0, sw = 0.0;
  for (int i = 0; i <= kSimpsonIntervals; ++i) {
    const double weight = (i == 0 || i == kSimpsonIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double a = angle_at(i * step);
    su += weight * std::cos(a);
    sw += weight * std::sin(a);
  }
  u = su * step / 3.0;
  w = sw * step / 3.0;
  angle = angle_at(h);
}

}  // namespace

const char* extensionStatusName(ExtensionStatus status) {
  switch (status) {
    case ExtensionStatus::kReached:
      return "reached";
    case ExtensionStatus::kTruncated:
      return "truncated";
    case ExtensionStatus::kOffMap:
      return "off_map";
    case ExtensionStatus::kLethal:
      return "lethal";
    case ExtensionStatus::kAttitude:
      return "attitude";
    case ExtensionStatus::kPitch:
      return "pitch";
    case ExtensionStatus::kRoll:
      return "roll";
    case ExtensionStatus::kSpeed:
      return "speed";
    case ExtensionStatus::kUnreachable:
      return "unreachable";
  }
  return "unknown";
}

ExtensionIntegrator::ExtensionIntegrator(const PlanningProblem& problem,
                                         const IntegrationSettings& settings)
    : problem_(&problem), settings_(settings), steering_(problem.limits) {
  const double cell = problem.map->geometry().cell;
  const double reach_m = problem.vehicle->samplingRadius() + kChordSlackM;
  near_no_data_ =
      terrain::noDataBand(*problem.map, problem.vehicle->surface().stencilReach() +
                                            static_cast<int>(std::ceil(reach_m / cell)));
}

models::TrajectorySample trajectorySample(const PathPoint& point, double t0) {
  models::TrajectorySample sample;
  sample.t = t0 + point.t;
  sample.x = point.position.x();
  sample.y = point.position.y();
  sample.z = point.z;
  sample.heading = point.heading;
  sample.roll = point.roll;
  sample.pitch = point.pitch;
  sample.v = point.v;
  sample.omega = point.v * point.curvature;
  sample.curvature = point.curvature;
  return sample;
}

bool ExtensionIntegrator::attitudeAt(PathPoint& point, ExtensionStatus& status) {
  const models::AttitudeStatus result = problem_->vehicle->compute(
      {point.position.x(), point.position.y(), point.heading}, workspace_, attitude_);
  if (result != models::AttitudeStatus::kOk) {
    status = result == models::AttitudeStatus::kNoTerrain ? ExtensionStatus::kOffMap
                                                          : ExtensionStatus::kAttitude;
    return false;
  }
  point.z = attitude_.attitude.z;
  point.roll = attitude_.attitude.roll;
  point.pitch = attitude_.attitude.pitch;
  if (std::abs(point.pitch) > problem_->limits.pitch_max) {
    status = ExtensionStatus::kPitch;
    return false;
  }
  if (std::abs(point.roll) > problem_->limits.roll_max) {
    status = ExtensionStatus::kRoll;
    return false;
  }
  return true;
}

bool ExtensionIntegrator::chordPlaceable(const PathPoint& a, const PathPoint& b) {
  if (near_no_data_.empty()) return true;
  const terrain::GridGeometry& geometry = problem_->map->geometry();
  const auto near = [&](const Eigen::Vector2d& p) {
    const std::optional<terrain::CellIndex> c = geometry.cellAt(p);
    return !c || near_no_data_[geometry.linearIndex(*c)] != 0;
  };
  if (!near(a.position) && !near(b.position)) return true;
  // Where the chord crosses a line of the half-cell grid (the cells' edges and centres: the
  // stencil a surface reads changes only there, so the point model's placement is constant
  // between two crossings), and every quarter cell (a footprint turns along the chord); one
  // point checked between each two.
  const double half = 0.5 * geometry.cell;
  const Eigen::Vector2d d = b.position - a.position;
  chord_fractions_.assign({0.0, 1.0});
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) continue;
    const double lo = std::min(a.position[axis], b.position[axis]);
    const double hi = std::max(a.position[axis], b.position[axis]);
    for (double k = std::ceil(lo / half); k * half <= hi; k += 1.0) {
      chord_fractions_.push_back(std::clamp((k * half - a.position[axis]) / d[axis], 0.0, 1.0));
    }
  }
  const int steps = static_cast<int>(std::ceil(d.norm() / (kChordSpacingCells * geometry.cell)));
  for (int j = 1; j < steps; ++j) chord_fractions_.push_back(static_cast<double>(j) / steps);
  std::sort(chord_fractions_.begin(), chord_fractions_.end());
  const double turn = wrapAngle(b.heading - a.heading);
  for (std::size_t j = 1; j < chord_fractions_.size(); ++j) {
    const double f = 0.5 * (chord_fractions_[j - 1] + chord_fractions_[j]);
    const Eigen::Vector2d p = a.position + f * d;
    if (problem_->vehicle->compute({p.x(), p.y(), a.heading + f * turn}, chord_workspace_,
                                   chord_attitude_) != models::AttitudeStatus::kOk) {
      return false;
    }
  }
  return true;
}

bool ExtensionIntegrator::segmentBlocked(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  const terrain::ElevationMap& map = *problem_->map;
  const terrain::GridGeometry& geometry = map.geometry();
  const terrain::GridLayer* lethal = map.findLayer(terrain::layer_names::kLethal);
  const auto blocked = [&](terrain::CellIndex c) {
    if (!geometry.isValid(c)) return true;
    if (std::isnan(map.elevation()(c))) return true;
    if (lethal == nullptr) return false;
    const float value = (*lethal)(c);
    return value != 0.0f && !std::isnan(value);
  };
  const std::optional<terrain::CellIndex> ca = geometry.cellAt(a);
  const std::optional<terrain::CellIndex> cb = geometry.cellAt(b);
  if (!ca || !cb) return true;
  if (blocked(*ca) || blocked(*cb)) return true;
  // A segment no longer than a cell crosses at most one more cell when it moves diagonally:
  // check both corner cells (conservative).
  if (ca->row != cb->row && ca->col != cb->col) {
    if (blocked({ca->row, cb->col}) || blocked({cb->row, ca->col})) return true;
  }
  return false;
}

double ExtensionIntegrator::pointCap(const PathPoint& point) const {
  const models::VehicleLimits& l = problem_->limits;
  double cap = l.v_max;
  if (point.curvature != 0.0) cap = std::min(cap, l.omega_max / std::abs(point.curvature));
  if (problem_->pitch_table != nullptr) {
    cap = std::min(cap, problem_->pitch_table->lookup(point.pitch));
  }
  if (problem_->roll_curvature_table != nullptr) {
    cap = std::min(cap, problem_->roll_curvature_table->lookup(point.roll, point.curvature));
  }
  return cap;
}

ExtensionStatus ExtensionIntegrator::extend(const PlannerState& from,
                                            const ExtensionRequest& request, Extension& out) {
  out.points.clear();
  segment_lengths_.clear();
  caps_.clear();
  out.duration = out.length = 0.0;
  const auto fail = [&](ExtensionStatus status) {
    out.status = status;
    return status;
  };
  // Cold start for every extension, so that re-running an edge reproduces it exactly.
  workspace_.has_warm_start = false;
  chord_workspace_.has_warm_start = false;
  const terrain::TerrainSurface& surface = problem_->vehicle->surface();
  const terrain::GridGeometry& geometry = problem_->map->geometry();
  const double ds = settings_.delta_g;
  const double end_tolerance = settings_.end_tolerance_fraction * ds;
  const TurnShape turn = steering_.turnShape(from.v, from.curvature, request.turn_speed);

  PathPoint point;
  point.position = from.position;
  point.heading = from.heading;
  point.curvature = from.curvature;
  ExtensionStatus status = ExtensionStatus::kReached;
  if (!attitudeAt(point, status)) return fail(status);
  if (segmentBlocked(point.position, point.position)) return fail(ExtensionStatus::kLethal);
  out.points.push_back(point);

  double turned = 0.0;
  ExtensionStatus outcome = ExtensionStatus::kTruncated;
  while (true) {
    const Eigen::Vector2d to_target = request.target - point.position;
    const double distance = to_target.norm();
    if (distance <= end_tolerance) {
      outcome = ExtensionStatus::kReached;
      break;
    }
    const double left = request.max_length - point.s;
    if (left <= 1e-9 * ds) break;  // kTruncated
    double heading_error = wrapAngle(std::atan2(to_target.y(), to_target.x()) - point.heading);
    // A heading error that would miss the target by less than a fraction of the end tolerance
    // needs no correction.
    if (std::abs(heading_error) * distance <= kLateralSlackFraction * end_tolerance) {
      heading_error = 0.0;
    }
    double h = std::min(ds, left);
    // Closing in on the target: end the step at the closest approach.
    const double along = distance * std::cos(heading_error);
    if (along < h && along > end_tolerance) h = along;

    // The final approach only straightens: close to the target its bearing swings with any
    // lateral offset.
    const double k1 = distance <= kFinalApproachSteps * ds
                          ? ContinuousCurvatureSteering::straighten(point.curvature, h, turn)
                          : steering_.nextCurvature(point.curvature, heading_error, h, turn);
    const std::optional<terrain::TangentPlanePatch> patch =
        terrain::TangentPlanePatch::at(surface, point.position, point.heading);
    if (!patch) return fail(ExtensionStatus::kOffMap);
    double u = 0.0, w = 0.0, angle = 0.0;
    clothoidStep(point.curvature, k1, h, u, w, angle);
    PathPoint next;
    next.position = patch->toMap(u, w).head<2>();
    next.heading = wrapAngle(patch->mapHeadingOf(angle));
    next.curvature = k1;
    next.s = point.s + h;
    if (!geometry.contains(next.position)) return fail(ExtensionStatus::kOffMap);
    if (segmentBlocked(point.position, next.position)) return fail(ExtensionStatus::kLethal);
    if (!attitudeAt(next, status)) return fail(status);
    if (!chordPlaceable(point, next)) return fail(ExtensionStatus::kOffMap);
    turned += std::abs(angle);
    if (turned > kMaxTurn) return fail(ExtensionStatus::kUnreachable);
    segment_lengths_.push_back(h);
    out.points.push_back(next);
    point = next;
  }

  // Speed caps: at each sample, and from the curvature rate of each segment on both its ends.
  caps_.resize(out.points.size());
  for (std::size_t i = 0; i < out.points.size(); ++i) caps_[i] = pointCap(out.points[i]);
  for (std::size_t i = 0; i < segment_lengths_.size(); ++i) {
    const double rate =
        std::abs(out.points[i + 1].curvature - out.points[i].curvature) / segment_lengths_[i];
    if (rate > 0.0) {
      const double cap = problem_->limits.sigma_max / rate;
      caps_[i] = std::min(caps_[i], cap);
      caps_[i + 1] = std::min(caps_[i + 1], cap);
    }
  }
  const double v_end = std::clamp(request.target_speed, 0.0, problem_->limits.v_max);
  if (profile_.compute(segment_lengths_, caps_, from.v, v_end, problem_->limits.a_max) !=
      SpeedProfileStatus::kOk) {
    return fail(ExtensionStatus::kSpeed);
  }
  const std::vector<double>& v = profile_.speeds();
  const std::vector<double>& t = profile_.times();
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    out.points[i].v = v[i];
    out.points[i].t = t[i];
  }
  const PathPoint& last = out.points.back();
  out.end = {last.position, last.heading, last.v, last.curvature};
  out.duration = profile_.duration();
  out.length = last.s;
  out.status = outcome;
  return outcome;
}

}  // namespace terratraj::search
