#include "terratraj/models/trajectory_checker.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace terratraj::models {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegreesPerRadian = 180.0 / kPi;
// Map points checked between two samples: every cell / this.
constexpr double kMapStepsPerCell = 8.0;

double wrapped(double angle) {
  double a = std::fmod(angle + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

// Keeps the worst violation of each rule.
class Violations {
 public:
  explicit Violations(const std::vector<TrajectorySample>& samples) : samples_(&samples) {}

  void add(const std::string& limit, double amount, std::size_t sample, double value = 0.0,
           double bound = 0.0) {
    auto it = worst_.find(limit);
    if (it != worst_.end() && !(amount > it->second.amount)) return;
    double t = sample < samples_->size() ? (*samples_)[sample].t : 0.0;
    if (!std::isfinite(t)) t = 0.0;
    worst_[limit] = CheckViolation{limit, amount, value, bound, sample, t};
  }
  // Adds `value - bound` when value exceeds bound by more than the slack.
  void above(const std::string& limit, double value, double bound, double slack,
             std::size_t sample) {
    if (!(value <= bound + slack)) {
      add(limit, std::isfinite(value) ? value - bound : 1.0, sample, value, bound);
    }
  }
  CheckReport report() const {
    CheckReport report;
    for (const auto& [name, violation] : worst_) {
      report.violations.push_back(violation);
      report.max_violation = std::max(report.max_violation, violation.amount);
    }
    return report;
  }

 private:
  const std::vector<TrajectorySample>* samples_;
  std::map<std::string, CheckViolation> worst_;
};

bool isAngle(const std::string& limit) {
  return limit == "pitch_max" || limit == "roll_max" || limit == "goal_heading" ||
         limit == "heading_of_motion" || limit == "pitch_column" || limit == "roll_column" ||
         limit == "segway_platform_pitch";
}

bool isStructural(const std::string& limit) {
  return limit == "lethal" || limit == "no_data" || limit == "off_map" || limit == "empty" ||
         limit == "finite" || limit == "attitude" || limit == "time_order";
}

std::string unitOf(const std::string& limit) {
  if (isAngle(limit)) return " rad";
  if (limit == "v_max" || limit == "v_min" || limit == "goal_speed" || limit == "start_speed" ||
      limit == "table_pitch" || limit == "table_roll_curvature" || limit == "segway_slope_v_max") {
    return " m/s";
  }
  if (limit == "a_max" || limit == "segway_slope_a_max") return " m/s^2";
  if (limit == "omega_max" || limit == "omega_equals_v_curvature") return " rad/s";
  if (limit == "kappa_max") return " 1/m";
  if (limit == "sigma_max") return " 1/(m s)";
  if (limit == "goal_position" || limit == "start_position" || limit == "motion") return " m";
  return "";
}

// "0.31 rad (17.8 deg)" for angles, "1.003 m/s" otherwise.
std::string withUnit(const std::string& limit, double value) {
  std::ostringstream text;
  text << value << unitOf(limit);
  if (isAngle(limit)) text << " (" << value * kDegreesPerRadian << " deg)";
  return text.str();
}

}  // namespace

const CheckViolation* CheckReport::find(const std::string& limit) const {
  for (const CheckViolation& v : violations) {
    if (v.limit == limit) return &v;
  }
  return nullptr;
}

std::string CheckReport::summary() const {
  if (ok()) return "ok";
  std::ostringstream text;
  for (std::size_t k = 0; k < violations.size(); ++k) {
    const CheckViolation& v = violations[k];
    if (k > 0) text << '\n';
    text << v.limit << ": ";
    if (isStructural(v.limit)) {
      text << "at row " << v.sample + 1 << ", t = " << v.t << " s";
      continue;
    }
    text << withUnit(v.limit, v.value) << " > " << withUnit(v.limit, v.bound) << " (by "
         << withUnit(v.limit, v.amount) << ") at row " << v.sample + 1 << ", t = " << v.t << " s";
  }
  return text.str();
}

namespace {

// The map rules at one point (the planners' footprint: the reference point).
void checkCell(const terrain::ElevationMap& map, double x, double y, std::size_t sample,
               Violations& found) {
  const std::optional<terrain::CellIndex> cell = map.geometry().cellAt({x, y});
  if (!cell) {
    found.add("off_map", 1.0, sample);
  } else if (map.isNoData(*cell)) {
    found.add("no_data", 1.0, sample);
  } else if (map.isLethal(*cell)) {
    found.add("lethal", 1.0, sample);
  }
}

// The rules at each sample: values, limits, map cell, attitude, tables.
void checkSamples(const std::vector<TrajectorySample>& s, const TrajectoryRequirements& r,
                  Violations& found) {
  const VehicleLimits& l = r.limits;
  const terrain::ElevationMap* map = r.map;
  const CheckTolerances& tol = r.tolerances;
  const auto slack = [&](double limit) { return tol.relative * std::abs(limit) + tol.absolute; };
  AttitudeWorkspace workspace;
  AttitudeResult attitude;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const TrajectorySample& p = s[i];
    const double values[] = {p.t,    p.x,     p.y, p.z,     p.heading,
                             p.roll, p.pitch, p.v, p.omega, p.curvature};
    if (!std::all_of(std::begin(values), std::end(values),
                     [](double v) { return std::isfinite(v); })) {
      found.add("finite", 1.0, i);
      continue;
    }
    if (p.v < -tol.absolute) found.add("v_min", -p.v, i, p.v, 0.0);
    found.above("v_max", p.v, l.v_max, slack(l.v_max), i);
    found.above("kappa_max", std::abs(p.curvature), l.kappa_max, slack(l.kappa_max), i);
    found.above("omega_max", std::abs(p.omega), l.omega_max, slack(l.omega_max), i);
    found.above("omega_equals_v_curvature", std::abs(p.omega - p.v * p.curvature), 0.0,
                slack(p.omega), i);
    if (map != nullptr) checkCell(*map, p.x, p.y, i, found);
    workspace.has_warm_start = false;
    if (r.vehicle->compute({p.x, p.y, p.heading}, workspace, attitude) != AttitudeStatus::kOk) {
      found.add("attitude", 1.0, i);
      continue;
    }
    const double pitch = attitude.attitude.pitch, roll = attitude.attitude.roll;
    found.above("pitch_max", std::abs(pitch), l.pitch_max, slack(l.pitch_max), i);
    found.above("roll_max", std::abs(roll), l.roll_max, slack(l.roll_max), i);
    found.above("pitch_column", std::abs(pitch - p.pitch), 0.0, tol.attitude, i);
    found.above("roll_column", std::abs(roll - p.roll), 0.0, tol.attitude, i);
    if (r.pitch_table != nullptr) {
      const double cap = r.pitch_table->lookup(pitch);
      found.above("table_pitch", p.v, cap, slack(cap), i);
    }
    if (r.roll_curvature_table != nullptr) {
      const double cap = r.roll_curvature_table->lookup(roll, p.curvature);
      found.above("table_roll_curvature", p.v, cap, slack(cap), i);
    }
    if (r.segway != nullptr) {
      const double cap = r.segway->bounds.speedLimit(pitch);
      found.above("segway_slope_v_max", p.v, cap, slack(cap), i);
    }
  }
}

// The Segway's rules between two samples (001_... III.C): the acceleration of the segment,
// (v_b - v_a) / dt, within the slope's a_max, and the platform pitch it causes within
// pitch_max. The slope is the terrain pitch (the samples' column, checked above); between the
// samples it lies between the two ends', so the bound is taken at the end where it is widest
// (a_max) or the pitch smallest (the platform): what the two samples alone can prove broken.
void checkSegwaySegment(const TrajectorySample& a, const TrajectorySample& b, double acceleration,
                        std::size_t i, const TrajectoryRequirements& r, Violations& found) {
  const CheckTolerances& tol = r.tolerances;
  const auto slack = [&](double limit) { return tol.relative * std::abs(limit) + tol.absolute; };
  const SegwayLookups& segway = *r.segway;
  const double a_cap =
      std::max(segway.bounds.accelerationLimit(a.pitch), segway.bounds.accelerationLimit(b.pitch));
  found.above("segway_slope_a_max", std::abs(acceleration), a_cap, slack(a_cap), i);
  const double platform = std::min(std::abs(segway.pitch_response.pitch(acceleration, a.pitch)),
                                   std::abs(segway.pitch_response.pitch(acceleration, b.pitch)));
  found.above("segway_platform_pitch", platform, r.limits.pitch_max, slack(r.limits.pitch_max), i);
}

// How far the heading of a segment whose curvature runs linearly (in arc length) from
// `kappa_a` to `kappa_b` [1/m] over `length` [m] goes beyond the range of its end headings
// [rad]: zero unless the curvature changes sign (an S-bend between two rows, as a planner's
// clothoid patches have), then max(kappa_a^2, kappa_b^2) length / (2 |kappa_a - kappa_b|). The
// direction of a chord is the heading at some point of the arc (the mean value theorem), so
// it lies within the end headings widened by this much.
double headingExcursion(double kappa_a, double kappa_b, double length) {
  if (!(kappa_a * kappa_b < 0.0)) return 0.0;
  return std::max(kappa_a * kappa_a, kappa_b * kappa_b) * length /
         (2.0 * std::abs(kappa_a - kappa_b));
}

// The rules between consecutive samples: time order, rates, motion, the swept map cells.
void checkSegments(const std::vector<TrajectorySample>& s, const TrajectoryRequirements& r,
                   Violations& found) {
  const VehicleLimits& l = r.limits;
  const terrain::ElevationMap* map = r.map;
  const CheckTolerances& tol = r.tolerances;
  const auto slack = [&](double limit) { return tol.relative * std::abs(limit) + tol.absolute; };
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const TrajectorySample& a = s[i];
    const TrajectorySample& b = s[i + 1];
    const double dt = b.t - a.t;
    if (!(dt > 0.0)) {
      found.add("time_order", 1.0, i + 1);
      continue;
    }
    found.above("a_max", std::abs(b.v - a.v) / dt, l.a_max, slack(l.a_max), i);
    if (r.segway != nullptr) checkSegwaySegment(a, b, (b.v - a.v) / dt, i, r, found);
    found.above("sigma_max", std::abs(b.curvature - a.curvature) / dt, l.sigma_max,
                slack(l.sigma_max), i);
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double distance = std::hypot(dx, dy);
    if (!std::isfinite(distance)) continue;
    const double drivable = 0.5 * (a.v + b.v) * dt;
    found.above("motion", distance, drivable, slack(drivable), i);
    if (distance > 1e-9) {
      const double mean_heading = a.heading + 0.5 * wrapped(b.heading - a.heading);
      const double off = std::abs(wrapped(std::atan2(dy, dx) - mean_heading));
      found.above("heading_of_motion", off,
                  tol.heading + 0.5 * std::abs(wrapped(b.heading - a.heading)) +
                      headingExcursion(a.curvature, b.curvature, distance),
                  0.0, i);
    }
    if (map == nullptr) continue;
    const int steps = std::max(
        1, static_cast<int>(std::ceil(distance * kMapStepsPerCell / map->geometry().cell)));
    for (int k = 1; k < steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      checkCell(*map, a.x + f * dx, a.y + f * dy, i, found);
    }
  }
}

void checkEndpoints(const std::vector<TrajectorySample>& s, const TrajectoryRequirements& r,
                    Violations& found) {
  if (r.start) {
    const TrajectorySample& first = s.front();
    const StartRequirement& start = *r.start;
    found.above("start_position",
                std::hypot(first.x - start.position.x(), first.y - start.position.y()), 0.0,
                start.position_tolerance, 0);
    found.above("start_speed", std::abs(first.v - start.v), 0.0, start.speed_tolerance, 0);
  }
  if (r.goal) {
    const std::size_t n = s.size() - 1;
    const TrajectorySample& last = s.back();
    const GoalRequirement& goal = *r.goal;
    found.above("goal_position", std::hypot(last.x - goal.position.x(), last.y - goal.position.y()),
                goal.position_tolerance, 0.0, n);
    if (goal.heading_tolerance < kPi) {
      found.above("goal_heading", std::abs(wrapped(last.heading - goal.heading)),
                  goal.heading_tolerance, 0.0, n);
    }
    found.above("goal_speed", std::abs(last.v - goal.v), goal.speed_tolerance, 0.0, n);
  }
}

}  // namespace

CheckReport checkTrajectory(const Trajectory& trajectory,
                            const TrajectoryRequirements& requirements) {
  const std::vector<TrajectorySample>& s = trajectory.samples;
  Violations found(s);
  if (s.empty()) {
    found.add("empty", 1.0, 0);
    return found.report();
  }
  if (requirements.vehicle == nullptr) {
    found.add("empty", 1.0, 0);  // nothing to check against: never passes
    return found.report();
  }
  checkSamples(s, requirements, found);
  checkSegments(s, requirements, found);
  checkEndpoints(s, requirements, found);
  return found.report();
}

}  // namespace terratraj::models
