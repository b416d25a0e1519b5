#pragma once
// KinodynamicPrm: the control-driven probabilistic roadmap of Kobilarov & Sukhatme (001_...
// IV), after Feron, Frazzoli & Dahleh's expansion, on terrain.
//
// solve(condition) grows a tree in state x time from the start:
//  1. sample a milestone: a position (uniform over the map; with probability goal_bias a point
//     on the goal's approach axis; after the first solution only inside the ellipse where
//     L-(s0, m) + L-(m, goal) can beat the best cost) and a speed;
//  2. gather nearby nodes from a spatial index and try them in ascending order of the
//     bang-bang lower bound L-(s, m) (after the first solution, optionally of
//     L(s0, s) + L-(s, m), Feron et al.'s optimisation mode) until one extension
//     (ExtensionIntegrator) is feasible; a failed one is "trapped";
//  3. branch and bound: keep the new node s_r only if L(s0, s_r) + L-(s_r, s_f) < L+(s0, s_f);
//  4. from a new node within reach of the goal, try to connect to the goal region; a better
//     connection becomes the best solution, and nodes that can no longer beat it are pruned.
// It keeps going after the first solution until the condition stops it (anytime), recording
// every improvement. Deterministic for a seed and a condition without a time limit.

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "terratraj/search/bang_bang_bound.hpp"
#include "terratraj/search/extension_integrator.hpp"
#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/planner.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/prm_roadmap.hpp"
#include "terratraj/search/spatial_grid_index.hpp"
#include "terratraj/search/termination_condition.hpp"

namespace terratraj::search {

/// Tuning of the PRM. Defaults are the ones the benchmarks and docs/planning.md use.
struct PrmOptions {
  std::uint64_t seed = 1;                  ///< std::mt19937_64 seed
  double delta_g_fraction = 0.5;           ///< patch length delta_g as a fraction of the cell size
  double extension_length_m = 8.0;         ///< d_max: longest extension toward a milestone [m]
  double goal_connection_radius_m = 12.0;  ///< try the goal from nodes this close [m]
  double goal_bias = 0.1;  ///< probability of a milestone on the goal's approach axis
  /// Goal-axis milestones lie up to this far behind the goal [m], within 0.8 of the heading
  /// tolerance of its axis.
  double approach_axis_length_m = 10.0;
  double full_speed_fraction = 0.5;  ///< probability that a milestone's speed is v_max
  std::size_t candidates = 6;        ///< most nodes tried per milestone
  std::size_t gather_count = 16;  ///< nodes gathered from the index per milestone (>= candidates)
  double bucket_size_m = 4.0;     ///< spatial index bucket [m]
  bool total_cost_order_after_solution = true;  ///< optimisation mode (see above)
  std::size_t reserve_nodes = 4096;             ///< nodes reserved up front
  std::size_t max_nodes = 2000000;              ///< stop growing (no_solution reason) beyond this
};

/// The planner. Keeps its roadmap between solve() calls (a replanning loop continues it);
/// clear() starts over.
class KinodynamicPrm final : public Planner {
 public:
  /// `problem` must outlive the planner; it is not validated here (PlanningProblem::validate).
  KinodynamicPrm(const PlanningProblem& problem, const PrmOptions& options = {});

  /// Grows the roadmap until `condition` stops it: the first call (or the first after clear())
  /// starts it from the start state with the generator seeded; later calls continue it (its
  /// nodes, best solution and generator), so two calls of 300 iterations end where one of 600
  /// does. The result's counters, cost history and times count from that first call, times in
  /// planning time summed over the calls [ms]. Never throws for planning failures: they are a
  /// kNoSolution status with a reason (a time limit of 0, no solution in time, the node cap).
  /// std::bad_alloc may escape.
  PlanResult solve(TerminationCondition condition) override;

  /// Forgets the roadmap, the best solution and the counters; re-seeds the generator. The next
  /// solve() plans from scratch, exactly as the first after construction did.
  void clear() override;

  /// "prm".
  const char* name() const override { return "prm"; }

  /// The roadmap of the last solve() (empty before the first).
  const PrmRoadmap& roadmap() const { return roadmap_; }
  /// The options in use (candidates >= 1, gather_count >= candidates).
  const PrmOptions& options() const { return options_; }
  /// delta_g [m] (delta_g_fraction x cell size, clamped) and the end tolerance.
  const IntegrationSettings& integrationSettings() const { return integrator_.settings(); }

  /// Re-runs the edges from the root to node `id` (and, if given, a final edge from that node)
  /// into one trajectory with every contract column; writes its arc length to `length_m`.
  models::Trajectory trajectoryTo(std::int32_t id, const ExtensionRequest* final_edge,
                                  double& length_m);

 private:
  double uniform();  // [0, 1)
  // Planning time of the earlier calls plus this one's so far [ms] (the result's clock).
  double plannedMs(const TerminationCondition& condition) const;
  bool sampleMilestone(Eigen::Vector2d& position, double& speed);
  std::int32_t addNode(const PrmNode& node);
  void tryGoalConnection(std::int32_t id, double elapsed_ms, PlanResult& result);
  // The sampling loop of solve(): milestones until the condition stops it or the node cap;
  // returns why it stopped (the reason when no solution was found).
  std::string growRoadmap(TerminationCondition& condition, PlanResult& result);
  // Extends the best-ranked node near `milestone` (speed [m/s]) that can still improve the
  // best solution towards it (at most options_.candidates tries); `milestone_to_goal` [s] is a
  // lower bound from the milestone to the goal.
  void extendTowards(const Eigen::Vector2d& milestone, double milestone_speed,
                     double milestone_to_goal, TerminationCondition& condition, PlanResult& result);
  void recordSolution(std::int32_t id, const ExtensionRequest* edge, double cost, double elapsed_ms,
                      PlanResult& result);
  void pruneNodes();
  bool blockedCell(const Eigen::Vector2d& position) const;

  const PlanningProblem* problem_;
  PrmOptions options_;
  BangBangBound bound_;
  ExtensionIntegrator integrator_;
  PrmRoadmap roadmap_;
  SpatialGridIndex index_;
  std::mt19937_64 rng_;
  Extension extension_;       // scratch
  Extension goal_extension_;  // scratch
  std::vector<std::int32_t> gathered_;
  std::vector<std::pair<double, std::int32_t>> ranked_;
  std::size_t alive_nodes_ = 0;
  std::size_t pruned_nodes_ = 0;
  // Best solution so far: L+(s0, sf), the node it leaves from and its final edge.
  double best_cost_;
  std::int32_t best_node_ = kNoParent;
  ExtensionRequest best_edge_;
  bool has_best_edge_ = false;
  // Continuation across solve() calls: whether the roadmap holds its root, the planning time
  // of the calls so far [ms], and their counters, first solution and cost history.
  bool started_ = false;
  double planned_ms_ = 0.0;
  PlanResult progress_;
};

}  // namespace terratraj::search
