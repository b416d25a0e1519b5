#pragma once
// LatticePlanner: heuristic search over a LatticeGraph: A* (Hart, Nilsson & Raphael), or anytime
// repairing A* (ARA*, Likhachev, Gordon & Thrun 2003): weighted A* with a heuristic weight
// epsilon that decreases round by round to 1, reusing the previous round's search (INCONS), each
// round's path epsilon-suboptimal; within the termination condition it returns the best path
// found. At epsilon 1 the path is optimal on the lattice (the heuristic is admissible).
//
// The start is the graph's start state; the goal is any state in the goal region (reaching it
// ends a path: goal states are not expanded). The trajectory is LatticeGraph::trajectory() of
// the path; PlanResult::cost_history records each new best trajectory duration.

#include <cstddef>
#include <memory>

#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/planner.hpp"
#include "terratraj/search/termination_condition.hpp"

namespace terratraj::search {

/// The search algorithm.
enum class LatticeAlgorithm {
  kAStar,    ///< one round at epsilon 1
  kAraStar,  ///< rounds at initial_epsilon, ..., 1 (anytime)
};

/// "astar", "arastar".
const char* latticeAlgorithmName(LatticeAlgorithm algorithm);

/// Settings of a LatticePlanner.
struct LatticePlannerOptions {
  LatticeAlgorithm algorithm = LatticeAlgorithm::kAraStar;
  double initial_epsilon = 3.0;  ///< ARA*: first heuristic weight, >= 1
  double epsilon_step = 0.5;     ///< ARA*: decrease per round, > 0 (the last round is at 1)
};

/// A* / ARA* on one graph. One solve() at a time; the graph must outlive the planner.
class LatticePlanner final : public Planner {
 public:
  explicit LatticePlanner(const LatticeGraph& graph, const LatticePlannerOptions& options = {});
  ~LatticePlanner() override;
  LatticePlanner(const LatticePlanner&) = delete;
  LatticePlanner& operator=(const LatticePlanner&) = delete;

  /// Searches until the termination condition (its iteration budget counts this call's
  /// expansions), the optimal round finishes, or the open list empties (no path: kNoSolution
  /// with a reason). Called again, it continues where the last call stopped (the same round,
  /// or the next epsilon; an ARA* stopped by a time limit goes on improving), and a finished
  /// search answers at once with its result: a replanning loop's use. Counts, cost history
  /// and times run from the first call (times in planning time summed over the calls [ms]).
  /// A graph with error() set gives kNoSolution with that error as the reason. Never throws
  /// (except std::bad_alloc).
  PlanResult solve(TerminationCondition termination) override;

  /// "lattice".
  const char* name() const override { return "lattice"; }
  /// Drops the search: the next solve() starts from the start state at initial_epsilon.
  void clear() override;

  const LatticePlannerOptions& options() const { return options_; }

 private:
  struct Progress;
  const LatticeGraph* graph_;
  LatticePlannerOptions options_;
  std::unique_ptr<Progress> progress_;
};

}  // namespace terratraj::search
