#include "terratraj/search/trajectory_checker.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace terratraj::search {

namespace {

constexpr double kPi = 3.14159265358979323846;
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
  void add(const std::string& limit, double amount, std::size_t sample) {
    auto it = worst_.find(limit);
    if (it == worst_.end()) {
      worst_.emplace(limit, CheckViolation{limit, amount, sample});
    } else if (amount > it->second.amount) {
      it->second.amount = amount;
      it->second.sample = sample;
    }
  }
  // Adds `value - limit` when value exceeds limit by more than the slack.
  void above(const std::string& limit, double value, double bound, double slack,
             std::size_t sample) {
    if (!(value <= bound + slack)) add(limit, std::isfinite(value) ? value - bound : 1.0, sample);
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
  std::map<std::string, CheckViolation> worst_;
};

}  // namespace

std::string CheckReport::summary() const {
  if (ok()) return "ok";
  std::ostringstream text;
  for (const CheckViolation& v : violations) {
    text << v.limit << ": exceeded by " << v.amount << " at sample " << v.sample << '\n';
  }
  return text.str();
}

CheckReport TrajectoryChecker::check(const models::Trajectory& trajectory,
                                     bool check_endpoints) const {
  Violations found;
  const std::vector<models::TrajectorySample>& s = trajectory.samples;
  if (s.empty()) {
    found.add("empty", 1.0, 0);
    return found.report();
  }
  const models::VehicleLimits& l = problem_->limits;
  const terrain::ElevationMap& map = *problem_->map;
  const terrain::GridGeometry& geometry = map.geometry();
  const double rel = tolerances_.relative, abs = tolerances_.absolute;
  const auto slack = [&](double limit) { return rel * std::abs(limit) + abs; };

  const auto check_cell = [&](double x, double y, std::size_t i) {
    const std::optional<terrain::CellIndex> cell = geometry.cellAt({x, y});
    if (!cell) {
      found.add("off_map", 1.0, i);
    } else if (map.isNoData(*cell)) {
      found.add("no_data", 1.0, i);
    } else if (map.isLethal(*cell)) {
      found.add("lethal", 1.0, i);
    }
  };

  models::AttitudeWorkspace workspace;
  models::AttitudeResult attitude;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const models::TrajectorySample& p = s[i];
    const double values[] = {p.t,    p.x,     p.y, p.z,     p.heading,
                             p.roll, p.pitch, p.v, p.omega, p.curvature};
    if (!std::all_of(std::begin(values), std::end(values),
                     [](double v) { return std::isfinite(v); })) {
      found.add("finite", 1.0, i);
      continue;
    }
    if (p.v < -abs) found.add("v_min", -p.v, i);
    found.above("v_max", p.v, l.v_max, slack(l.v_max), i);
    found.above("kappa_max", std::abs(p.curvature), l.kappa_max, slack(l.kappa_max), i);
    found.above("omega_max", std::abs(p.omega), l.omega_max, slack(l.omega_max), i);
    found.above("omega_equals_v_curvature", std::abs(p.omega - p.v * p.curvature), 0.0,
                slack(p.omega), i);
    check_cell(p.x, p.y, i);
    workspace.has_warm_start = false;
    if (problem_->vehicle->compute({p.x, p.y, p.heading}, workspace, attitude) !=
        models::AttitudeStatus::kOk) {
      found.add("attitude", 1.0, i);
      continue;
    }
    const double pitch = attitude.attitude.pitch, roll = attitude.attitude.roll;
    found.above("pitch_max", std::abs(pitch), l.pitch_max, slack(l.pitch_max), i);
    found.above("roll_max", std::abs(roll), l.roll_max, slack(l.roll_max), i);
    found.above("pitch_column", std::abs(pitch - p.pitch), 0.0, tolerances_.attitude, i);
    found.above("roll_column", std::abs(roll - p.roll), 0.0, tolerances_.attitude, i);
    if (problem_->pitch_table != nullptr) {
      const double cap = problem_->pitch_table->lookup(pitch);
      found.above("table_pitch", p.v, cap, slack(cap), i);
    }
    if (problem_->roll_curvature_table != nullptr) {
      const double cap = problem_->roll_curvature_table->lookup(roll, p.curvature);
      found.above("table_roll_curvature", p.v, cap, slack(cap), i);
    }
  }

  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const models::TrajectorySample& a = s[i];
    const models::TrajectorySample& b = s[i + 1];
    const double dt = b.t - a.t;
    if (!(dt > 0.0)) {
      found.add("time_order", 1.0, i);
      continue;
    }
    found.above("a_max", std::abs(b.v - a.v) / dt, l.a_max, slack(l.a_max), i);
    found.above("sigma_max", std::abs(b.curvature - a.curvature) / dt, l.sigma_max,
                slack(l.sigma_max), i);
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double distance = std::hypot(dx, dy);
    const double drivable = 0.5 * (a.v + b.v) * dt;
    found.above("motion", distance, drivable, slack(drivable), i);
    if (distance > 1e-9) {
      const double mean_heading = a.heading + 0.5 * wrapped(b.heading - a.heading);
      const double off = std::abs(wrapped(std::atan2(dy, dx) - mean_heading));
      found.above("heading_of_motion", off,
                  tolerances_.heading + 0.5 * std::abs(wrapped(b.heading - a.heading)), 0.0, i);
    }
    const int steps =
        std::max(1, static_cast<int>(std::ceil(distance * kMapStepsPerCell / geometry.cell)));
    for (int k = 1; k < steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      check_cell(a.x + f * dx, a.y + f * dy, i);
    }
  }

  if (check_endpoints) {
    const models::TrajectorySample& first = s.front();
    const PlannerState& start = problem_->start;
    found.above("start_position",
                std::hypot(first.x - start.position.x(), first.y - start.position.y()), 0.0, 1e-6,
                0);
    found.above("start_speed", std::abs(first.v - start.v), 0.0, 1e-9, 0);
    const models::TrajectorySample& last = s.back();
    const PlannerState end{{last.x, last.y}, last.heading, last.v, last.curvature};
    if (!problem_->goal.contains(end)) found.add("goal_region", 1.0, s.size() - 1);
  }
  return found.report();
}

}  // namespace terratraj::search
