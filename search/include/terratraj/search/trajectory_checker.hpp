#pragma once
// TrajectoryChecker: re-checks a finished trajectory against every limit and the map,
// independently of the planner that produced it. It reads only the trajectory's samples (the
// contract's columns), differentiates them by finite differences, recomputes the attitude with
// the vehicle model, and walks the map between samples; it shares no code with the planner's
// own checks (ExtensionIntegrator).
//
// Checked: times strictly increasing; 0 <= v <= v_max; |dv/dt| <= a_max between samples;
// |curvature| <= kappa_max; |omega| <= omega_max and omega = v curvature; |d curvature / dt| <=
// sigma_max between samples; horizontal motion no longer than the distance the speeds allow;
// the direction of motion along the heading; pitch and roll recomputed by the attitude model
// within the limits (and equal to the file's columns); v within the tables; no lethal or
// no-data cell under the samples or under points every cell / 8 between them. Optionally the
// first sample is the start and the last lies in the goal region.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/search/planning_problem.hpp"

namespace terratraj::search {

/// One broken rule: which, by how much (in the limit's own units) and where.
struct CheckViolation {
  std::string limit;       ///< e.g. "v_max", "a_max", "sigma_max", "pitch_max", "lethal"
  double amount = 0.0;     ///< excess over the limit (> 0); 1 for map and structure rules
  std::size_t sample = 0;  ///< index of the (first) sample involved
};

/// The outcome of a check.
struct CheckReport {
  std::vector<CheckViolation>
      violations;              ///< the worst violation of each rule, at most one per rule
  double max_violation = 0.0;  ///< largest amount (0 when all hold)
  bool ok() const { return violations.empty(); }
  /// "ok" or one line per violation.
  std::string summary() const;
};

/// Relative and absolute slack of the checks (finite differences of printed values).
struct CheckTolerances {
  double relative = 1e-6;  ///< fraction of each limit
  double absolute = 1e-9;  ///< in the limit's units
  double heading = 0.05;   ///< direction of motion vs heading [rad]
  double attitude = 1e-4;  ///< recomputed pitch / roll vs the columns [rad] (iterative models)
};

/// Checks trajectories against one problem (its map, vehicle, limits, tables, start, goal).
class TrajectoryChecker {
 public:
  /// `problem` must outlive the checker.
  explicit TrajectoryChecker(const PlanningProblem& problem, const CheckTolerances& tolerances = {})
      : problem_(&problem), tolerances_(tolerances) {}

  /// Checks the limits and the map; with `check_endpoints`, also that the first sample is the
  /// start (position within 1e-6 m, speed) and that the last lies in the goal region.
  CheckReport check(const models::Trajectory& trajectory, bool check_endpoints = true) const;

 private:
  const PlanningProblem* problem_;
  CheckTolerances tolerances_;
};

}  // namespace terratraj::search
