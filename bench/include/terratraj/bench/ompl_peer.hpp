#pragma once
// OMPL peers of the planners suite (`terratraj bench planners`): OMPL 1.5's control-based RRT
// (with our steering function) and SST (time as the cost) on a search::PlanningProblem, with
// the same propagator (search::ExtensionIntegrator: an OMPL control is an extension request,
// a target and a target speed) and the same validity checks (the integrator's: map, lethal
// cells, pitch, roll, speed caps and tables). OMPL is a benchmark peer only.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/search/planning_problem.hpp"

namespace terratraj::bench {

enum class OmplPlanner { kRrt, kSst };
/// "ompl_rrt", "ompl_sst".
inline const char* omplPlannerName(OmplPlanner planner) {
  return planner == OmplPlanner::kRrt ? "ompl_rrt" : "ompl_sst";
}

/// Whether this build has the peers (false with -DTERRATRAJ_WITH_OMPL=OFF: runOmplPeer() then
/// returns an unsolved run whose status says so).
bool omplPeersAvailable();

/// One OMPL run.
struct OmplRun {
  bool solved = false;             ///< an exact solution (the goal region reached)
  std::string status;              ///< OMPL's PlannerStatus as text
  std::optional<double> first_ms;  ///< time to the first exact solution [ms]
  std::vector<std::pair<double, double>> cost_history;  ///< (ms, duration [s]) per improvement
  double planning_ms = 0.0;                             ///< the whole solve() [ms]
  /// The best solution re-integrated with the extension integrator (every column filled);
  /// its duration is the cost reported.
  models::Trajectory trajectory;
  double cost_s = 0.0;
};

/// Runs `planner` on `problem` for at most `budget_s` seconds (RRT stops at its first
/// solution). OMPL's random seed is process-wide: it is set from `seed` on the first call
/// only (later calls in the same process continue its sequence). Never throws for a failed
/// plan (solved false, status says why).
OmplRun runOmplPeer(const search::PlanningProblem& problem, OmplPlanner planner, double budget_s,
                    std::uint64_t seed);

}  // namespace terratraj::bench
