#include "terratraj/search/taeasl_planner.hpp"

#include "terratraj/search/plan_verdict.hpp"
#include "terratraj/search/trajectory_checker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "lattice_search_core.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace terratraj::search {
namespace {

using detail::millisecondsSince;
using detail::QueueEntry;
using detail::SearchNode;

constexpr int kStateKeyBits = 42;
constexpr std::size_t kConfirmEvery = 256;  // expansions between optimality checks

class FramesAdapter final : public detail::ReferenceFramesAdapter {
 public:
  explicit FramesAdapter(const ReferenceFrames& frames) : frames_(&frames) {}
  void crossings(const std::vector<Eigen::Vector2d>& points,
                 HomotopySignature& signature) const override {
    for (std::size_t k = 1; k < points.size(); ++k) {
      frames_->appendCrossings(points[k - 1], points[k], signature);
    }
  }

 private:
  const ReferenceFrames* frames_;
};

// One homotopy class: its signature, open list and best goal.
struct HomotopyClass {
  HomotopySignature signature;
  detail::OpenList open;
  std::int32_t best_goal = -1;
  double best_goal_g = std::numeric_limits<double>::infinity();
  double found_ms = 0.0;
  bool final = false;   // proven cheapest in its class
  bool active = false;  // in the round-robin list
};

}  // namespace

const char* frameAnchorName(FrameAnchor anchor) {
  switch (anchor) {
    case FrameAnchor::kMapCenter:
      return "map_center";
    case FrameAnchor::kStart:
      return "start";
    case FrameAnchor::kMidpoint:
      return "midpoint";
  }
  return "unknown";
}

TaeaslPlanner::TaeaslPlanner(const LatticeGraph& graph, const TaeaslOptions& options)
    : graph_(&graph), options_(options) {
  const PlanningProblem& problem = graph.problem();
  const terrain::GridGeometry& geometry = problem.map->geometry();
  switch (options.anchor) {
    case FrameAnchor::kMapCenter:
      anchor_ = {0.5 * geometry.width(), 0.5 * geometry.height()};
      break;
    case FrameAnchor::kStart:
      anchor_ = problem.start.position;
      break;
    case FrameAnchor::kMidpoint:
      anchor_ = 0.5 * (problem.start.position + problem.goal.position);
      break;
  }
  ReferenceFrameOptions frame_options;
  frame_options.anchor = anchor_;
  frame_options.frame_radius = options.frame_radius;
  frames_ = ReferenceFrames::build(*problem.map, terrain::findObstacleClusters(*problem.map),
                                   frame_options);
  max_signature_length_ = options.max_signature_length > 0
                              ? options.max_signature_length
                              : 2 * static_cast<int>(frames_.size()) + 2;
}

PlanResult TaeaslPlanner::solve(TerminationCondition termination) const {
  const auto started = std::chrono::steady_clock::now();
  termination.start();
  PlanResult result;
  const LatticeGraph& graph = *graph_;
  SearchStatistics& stats = result.search;
  stats.frames = frames_.size();
  const auto finish = [&](PlanResult& r) -> PlanResult {
    r.planning_time_ms = millisecondsSince(started);
    return r;
  };
  if (graph.error()) {
    result.reason = *graph.error();
    return finish(result);
  }
  if (options_.homotopy_classes < 1) {
    result.reason = "homotopy_classes: must be >= 1";
    return finish(result);
  }
  if (graph.inGoal(graph.start())) {
    planStartInGoal(graph.problem(), result);  // nothing to drive: the one-row trajectory
    return finish(result);
  }
  const double w = std::max(1.0, options_.heuristic_weight);
  // Without frames there is one class: stop once its path is proven.
  const int wanted = frames_.empty() ? 1 : options_.homotopy_classes;
  const bool provable = w == 1.0;

  std::vector<SearchNode> nodes;
  nodes.reserve(1 << 15);
  detail::FlatHashMap<std::int32_t> index(1 << 15);
  detail::EdgeCache cache(graph);
  const FramesAdapter adapter(frames_);
  std::vector<HomotopyClass> classes;
  std::unordered_map<HomotopySignature, std::int32_t, HomotopySignatureHash> class_of;
  std::vector<std::int32_t> active;
  std::size_t cursor = 0;

  const auto classIndex = [&](const HomotopySignature& signature) {
    const auto [it, inserted] =
        class_of.emplace(signature, static_cast<std::int32_t>(classes.size()));
    if (inserted) {
      classes.emplace_back();
      classes.back().signature = signature;
    }
    return it->second;
  };
  const auto nodeKey = [&](const LatticeState& s, std::int32_t klass) {
    return (static_cast<std::uint64_t>(klass) << kStateKeyBits) | graph.key(s);
  };
  const auto activate = [&](std::int32_t klass) {
    if (!classes[klass].active) {
      classes[klass].active = true;
      active.push_back(klass);
    }
  };

  const LatticeState start = graph.start();
  const std::int32_t root_class = classIndex(HomotopySignature());
  *index.insert(nodeKey(start, root_class)).first = 0;
  nodes.push_back({});
  nodes[0].state = start;
  nodes[0].g = 0.0;
  nodes[0].klass = root_class;
  classes[root_class].open.push({w * graph.heuristic(start), 0.0, 0});
  activate(root_class);

  // Drops stale entries from the top of a class's list.
  const auto clean = [&](HomotopyClass& c) {
    while (!c.open.empty() && c.open.top().g != nodes[c.open.top().node].g) c.open.pop();
  };
  // Marks as final every candidate no open node can beat; returns how many are final.
  const auto confirm = [&]() {
    double lower = std::numeric_limits<double>::infinity();
    for (HomotopyClass& c : classes) {
      clean(c);
      if (!c.open.empty()) lower = std::min(lower, c.open.top().f);
    }
    int final_count = 0;
    for (HomotopyClass& c : classes) {
      if (c.best_goal >= 0 && c.best_goal_g <= lower) c.final = true;
      final_count += c.final ? 1 : 0;
    }
    return final_count;
  };

  // Pruning bound: the wanted-th cheapest candidate; a node with g + h at least this cannot
  // lead to one of the `wanted` cheapest classes (it would cost at least as much).
  double bound = std::numeric_limits<double>::infinity();
  std::vector<double> candidate_costs;
  const auto kthCandidateCost = [&]() {
    candidate_costs.clear();
    for (const HomotopyClass& c : classes) {
      if (c.best_goal >= 0) candidate_costs.push_back(c.best_goal_g);
    }
    if (static_cast<int>(candidate_costs.size()) < wanted) {
      return std::numeric_limits<double>::infinity();
    }
    std::nth_element(candidate_costs.begin(), candidate_costs.begin() + (wanted - 1),
                     candidate_costs.end());
    return candidate_costs[wanted - 1];
  };
  std::size_t expansions = 0;
  bool stopped = false;
  bool exhausted = false;
  HomotopySignature signature;
  // Once a class has reached the goal, the search stops at this share of the time limit: the
  // rest builds and checks the trajectories within the limit.
  constexpr double kSearchShare = 0.85;
  const double search_limit_s = kSearchShare * termination.timeLimitSeconds();
  while (true) {
    if ((expansions & 15u) == 0 &&
        (termination.shouldStop(expansions, false) ||
         (result.first_solution_ms && termination.elapsedSeconds() >= search_limit_s))) {
      stopped = true;
      break;
    }
    if (provable && expansions % kConfirmEvery == 0 && expansions > 0 && confirm() >= wanted) {
      break;
    }
    // Next class in turn with work.
    std::int32_t klass = -1;
    while (!active.empty()) {
      if (cursor >= active.size()) cursor = 0;
      HomotopyClass& c = classes[active[cursor]];
      clean(c);
      if (c.open.empty()) {
        c.active = false;
        active[cursor] = active.back();
        active.pop_back();
        continue;
      }
      klass = active[cursor];
      ++cursor;
      break;
    }
    if (klass < 0) {
      exhausted = true;
      break;
    }
    const QueueEntry top = classes[klass].open.top();
    classes[klass].open.pop();
    const std::int32_t current = top.node;
    const LatticeState s = nodes[current].state;
    const double g = nodes[current].g;
    if (g + graph.heuristic(s) >= bound) continue;  // cannot reach a wanted class
    const std::uint64_t s_key = graph.key(s);
    ++expansions;
    const int edges = graph.edgeCount(s);
    for (int e = 0; e < edges; ++e) {
      const LatticeState t = graph.target(s, e);
      if (!graph.onLattice(t)) continue;
      const detail::CachedEdge& edge = cache.get(s, s_key, e, stats, &adapter);
      if (!std::isfinite(edge.cost)) continue;
      const double g2 = g + edge.cost;
      std::int32_t next_class = klass;
      if (edge.crossings_count > 0) {
        signature = classes[klass].signature;
        const std::vector<FrameCrossing>& all = cache.crossings();
        for (std::uint32_t k = 0; k < edge.crossings_count; ++k) {
          signature.append(all[edge.crossings_begin + k]);
        }
        if (static_cast<int>(signature.size()) > max_signature_length_) {
          ++stats.pruned_signatures;
          continue;
        }
        next_class = classIndex(signature);
      }
      const bool goal = graph.inGoal(t);
      if (goal ? g2 >= classes[next_class].best_goal_g : g2 + graph.heuristic(t) >= bound) {
        continue;
      }
      const std::int32_t next =
          detail::findOrAddNode(index, nodes, nodeKey(t, next_class), t, next_class);
      SearchNode& m = nodes[next];
      if (!(g2 < m.g)) continue;
      m.g = g2;
      m.parent = current;
      m.edge = e;
      ++stats.generated;
      HomotopyClass& c = classes[next_class];
      if (goal) {
        c.best_goal = next;
        c.best_goal_g = g2;
        c.found_ms = millisecondsSince(started);
        if (!result.first_solution_ms) result.first_solution_ms = c.found_ms;
        bound = kthCandidateCost();
        continue;
      }
      c.open.push({g2 + w * graph.heuristic(t), g2, next});
      activate(next_class);
    }
  }
  if (provable && (exhausted || !stopped)) confirm();

  // The cheapest candidates, one per class.
  std::vector<std::int32_t> found;
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(classes.size()); ++c) {
    if (classes[c].best_goal >= 0) found.push_back(c);
  }
  std::sort(found.begin(), found.end(), [&](std::int32_t a, std::int32_t b) {
    return classes[a].best_goal_g < classes[b].best_goal_g ||
           (classes[a].best_goal_g == classes[b].best_goal_g &&
            classes[a].signature < classes[b].signature);
  });
  std::string last_failure;
  const models::TrajectoryRequirements requirements = requirementsOf(graph.problem());
  std::size_t built = 0;
  for (std::int32_t c : found) {
    if (static_cast<int>(result.solutions.size()) >= options_.homotopy_classes) break;
    // Past the time limit only the best class is still built: the limit holds.
    if (!result.solutions.empty() && termination.timeUp()) break;
    const HomotopyClass& k = classes[c];
    std::string why;
    std::optional<LatticeTrajectory> trajectory =
        graph.trajectory(detail::reconstructPath(nodes, k.best_goal), &why);
    ++built;
    if (!trajectory) {
      last_failure = k.signature.toString() + ": " + why;
      continue;
    }
    PlanSolution solution;
    solution.trajectory = std::move(trajectory->trajectory);
    solution.cost_s = trajectory->duration;
    solution.search_cost_s = trajectory->cost;
    solution.length_m = trajectory->length;
    solution.homotopy = k.signature.toString();
    solution.proven_optimal = provable && (k.final || exhausted);
    solution.found_ms = k.found_ms;
    if (admitSolution(requirements, std::move(solution), result)) {
      result.cost_history.push_back({k.found_ms, result.solutions.back().cost_s});
    }
  }
  stats.classes_found = found.size();
  stats.classes_built = built;
  std::sort(result.cost_history.begin(), result.cost_history.end(),
            [](const CostSample& a, const CostSample& b) { return a.time_ms < b.time_ms; });
  stats.expansions = expansions;
  stats.homotopy_classes = classes.size();
  stats.final_epsilon = w;
  result.nodes = nodes.size();
  result.statistics.iterations = expansions;
  result.statistics.attempts = stats.edge_evaluations;
  result.statistics.trapped = stats.invalid_edges;
  concludePlan(result);
  if (!result.solutions.empty()) {
    result.first_solution_cost_s = result.cost_history.front().cost_s;
  } else if (!result.rejected.empty()) {
    // concludePlan() said why.
  } else if (!last_failure.empty()) {
    result.reason = "the paths found have no trajectory: " + last_failure;
  } else if (exhausted) {
    result.reason = detail::exhaustedLatticeReason(graph, nodes.size());
  } else {
    std::ostringstream text;
    text << "no path within the termination condition (" << expansions << " expansions)";
    result.reason = text.str();
  }
  return finish(result);
}

}  // namespace terratraj::search
