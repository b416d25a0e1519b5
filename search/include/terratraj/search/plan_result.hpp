#pragma once
// PlanResult: what a planner returns: a status, the best trajectory, timings, roadmap
// statistics and the best cost over time (the anytime curve of 001_... figs. 6 and 7).

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/trajectory.hpp"
#include "terratraj/models/trajectory_checker.hpp"

namespace terratraj::search {

/// Whether a plan reached the goal region.
enum class PlanStatus {
  kSolved,      ///< a trajectory to the goal region was found
  kNoSolution,  ///< none within the termination condition (see PlanResult::reason)
};

/// "solved" / "no_solution" (the contract's names).
const char* planStatusName(PlanStatus status);

/// One point of the cost-versus-time curve: a new best cost and when it was found.
struct CostSample {
  double time_ms = 0.0;  ///< since the start of solve() [ms]
  double cost_s = 0.0;   ///< trajectory duration [s]
};

/// Counters of one solve().
struct PlanStatistics {
  std::size_t iterations = 0;        ///< milestones sampled
  std::size_t attempts = 0;          ///< extension attempts toward milestones
  std::size_t trapped = 0;           ///< attempts that failed (ExtensionStatus not succeeded)
  std::size_t pruned = 0;            ///< feasible extensions discarded by branch and bound
  std::size_t goal_attempts = 0;     ///< connections tried from a new node to the goal
  std::size_t goal_connections = 0;  ///< of which reached the goal region
  std::size_t improvements = 0;      ///< times the best cost improved
  std::size_t pruned_nodes = 0;      ///< nodes removed after an improvement
};

/// Counters of a lattice search (LatticePlanner, TaeaslPlanner).
struct SearchStatistics {
  std::size_t expansions = 0;         ///< nodes expanded
  std::size_t generated = 0;          ///< successor relaxations that improved a node
  std::size_t edge_evaluations = 0;   ///< edges evaluated on the terrain (cache misses)
  std::size_t invalid_edges = 0;      ///< of which were invalid
  std::size_t cache_hits = 0;         ///< edge evaluations answered by the cache
  std::size_t rounds = 0;             ///< ARA*: improvePath rounds run
  double final_epsilon = 1.0;         ///< ARA*: the heuristic weight of the last finished round
  std::size_t homotopy_classes = 0;   ///< TAEASL: classes (open lists) created
  std::size_t frames = 0;             ///< TAEASL: reference frames
  std::size_t pruned_signatures = 0;  ///< TAEASL: successors dropped for a too-long signature
  std::size_t classes_found = 0;      ///< TAEASL: classes whose search reached the goal
  std::size_t classes_built = 0;      ///< TAEASL: of which got a trajectory (the limit may stop it)
};

/// One returned solution (a lattice planner may return several, one per homotopy class).
struct PlanSolution {
  models::Trajectory trajectory;  ///< every column filled
  double cost_s = 0.0;            ///< trajectory duration (with the speed profile) [s]
  double search_cost_s = 0.0;     ///< the search's cost of the path [s]
  double length_m = 0.0;          ///< planar length [m]
  std::string homotopy;           ///< class signature ("" for planners without classes)
  /// Whether the search proved it the cheapest path in its class (TAEASL) or overall (A* /
  /// ARA* at epsilon 1), up to the lattice.
  bool proven_optimal = false;
  double found_ms = 0.0;      ///< when the search found it [ms]
  models::CheckReport check;  ///< the verdict's independent check (applyPlanVerdict)
};

/// A solution a planner found but the verdict (applyPlanVerdict) rejected.
struct RejectedSolution {
  double cost_s = 0.0;   ///< its duration [s]
  std::string homotopy;  ///< its class ("" without classes)
  std::string reason;    ///< the rules its written trajectory breaks
};

/// The outcome of a planner's solve().
struct PlanResult {
  PlanStatus status = PlanStatus::kNoSolution;
  std::string reason;                       ///< why there is no solution ("" when solved)
  std::optional<double> first_solution_ms;  ///< time to the first solution [ms]
  double first_solution_cost_s = std::numeric_limits<double>::infinity();
  double planning_time_ms = 0.0;  ///< whole solve() including the trajectory [ms]
  std::size_t nodes = 0;          ///< roadmap nodes at the end (root included)
  PlanStatistics statistics;
  /// Best cost (trajectory duration) [s]; +infinity without a solution.
  double best_cost_s = std::numeric_limits<double>::infinity();
  std::vector<CostSample> cost_history;  ///< one entry per improvement, in time order
  models::Trajectory trajectory;         ///< the best trajectory, every column filled
  double length_m = 0.0;                 ///< its arc length along the surface [m]
  /// Every solution, best first (the first is `trajectory`); one for the PRM. After
  /// applyPlanVerdict() only those that pass the verdict.
  std::vector<PlanSolution> solutions;
  SearchStatistics search;  ///< lattice planners' counters
  /// Solutions found but rejected by the verdict (applyPlanVerdict), in the order found.
  std::vector<RejectedSolution> rejected;

  /// trapped / attempts (0 without attempts).
  double trappedFraction() const {
    return statistics.attempts == 0
               ? 0.0
               : static_cast<double>(statistics.trapped) / static_cast<double>(statistics.attempts);
  }
};

}  // namespace terratraj::search
