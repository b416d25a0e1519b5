#pragma once
// judgeTrajectory(): the one place that decides whether a result may be called `converged`
// (solve, refine) or `solved` (plan): the contract's "Verdicts" (../shared/spec/interface.md).
// It takes the trajectory exactly as its CSV holds it (asWritten) and runs the independent
// checkTrajectory() on it: goal within the tolerances; no lethal, no-data or off-map cell under
// the swept path; every limit and table at every row within 1e-3 relative (1e-6 absolute).
// Every solver (ocp::solveBoundaryValue, ocp::solveTranscription), every planner's result
// (search::verifyPlanSolutions), every refinement and every bench row goes through it.

#include <string>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/trajectory_checker.hpp"

namespace terratraj::models {

/// Why a trajectory fails its verdict (the first that applies, in this order).
enum class VerdictFailure {
  kNone,          ///< it passes
  kUnusable,      ///< empty, not finite, times not increasing, not at the start
  kCrossesMap,    ///< over a lethal, no-data or off-map cell, or where the vehicle cannot rest
  kBreaksLimits,  ///< a limit or table broken at some row (beyond the tolerances)
  kMissesGoal,    ///< ends outside the goal's tolerances (and nothing else is wrong)
};

/// "none", "unusable", "crosses_map", "breaks_limits", "misses_goal".
const char* verdictFailureName(VerdictFailure failure);

/// The outcome of judgeTrajectory().
struct TrajectoryVerdict {
  VerdictFailure failure = VerdictFailure::kUnusable;
  /// A goal rule is broken (goal_position, goal_heading, goal_speed), beside whatever
  /// `failure` names first.
  bool misses_goal = false;
  CheckReport check;   ///< every rule broken, worst of each
  std::string reason;  ///< empty when it passes; else one line naming the rules, rows, amounts
  bool passes() const { return failure == VerdictFailure::kNone; }
};

/// `trajectory` with every value rounded as writeTrajectoryCsv() writes it (12 significant
/// digits): what a reader of the CSV sees. Never throws (except std::bad_alloc).
Trajectory asWritten(const Trajectory& trajectory);

/// Judges `trajectory` as written (asWritten) against `requirements`. Never throws (except
/// std::bad_alloc).
TrajectoryVerdict judgeTrajectory(const Trajectory& trajectory,
                                  const TrajectoryRequirements& requirements);

}  // namespace terratraj::models
