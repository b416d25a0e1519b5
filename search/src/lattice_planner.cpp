#include "terratraj/search/lattice_planner.hpp"

#include "terratraj/search/plan_verdict.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "lattice_search_core.hpp"

namespace terratraj::search {
namespace {

using detail::millisecondsSince;
using detail::QueueEntry;
using detail::SearchNode;

}  // namespace

const char* latticeAlgorithmName(LatticeAlgorithm algorithm) {
  return algorithm == LatticeAlgorithm::kAStar ? "astar" : "arastar";
}

LatticePlanner::LatticePlanner(const LatticeGraph& graph, const LatticePlannerOptions& options)
    : graph_(&graph), options_(options) {}

PlanResult LatticePlanner::solve(TerminationCondition termination) const {
  const auto started = std::chrono::steady_clock::now();
  termination.start();
  PlanResult result;
  const LatticeGraph& graph = *graph_;
  const auto finish = [&](PlanResult& r) -> PlanResult {
    applyPlanVerdict(graph.problem(), r);
    r.planning_time_ms = millisecondsSince(started);
    return r;
  };
  if (graph.error()) {
    result.reason = *graph.error();
    return finish(result);
  }
  if (graph.inGoal(graph.start())) {
    planStartInGoal(graph.problem(), result);  // nothing to drive: the one-row trajectory
    return finish(result);
  }
  const bool anytime = options_.algorithm == LatticeAlgorithm::kAraStar;
  double epsilon = anytime ? std::max(1.0, options_.initial_epsilon) : 1.0;
  const double step = options_.epsilon_step > 0.0 ? options_.epsilon_step : 0.5;

  std::vector<SearchNode> nodes;
  nodes.reserve(1 << 15);
  detail::FlatHashMap<std::int32_t> index(1 << 15);
  detail::EdgeCache cache(graph);
  detail::OpenList open;
  std::vector<std::int32_t> incons;
  SearchStatistics& stats = result.search;

  const LatticeState start = graph.start();
  *index.insert(graph.key(start)).first = 0;
  nodes.push_back({});
  nodes[0].state = start;
  nodes[0].g = 0.0;
  open.push({epsilon * graph.heuristic(start), 0.0, 0});

  std::int32_t best_goal = -1;
  double best_goal_g = std::numeric_limits<double>::infinity();
  double published_g = std::numeric_limits<double>::infinity();
  std::uint32_t round = 1;
  bool stopped = false;
  bool proven = false;
  std::size_t expansions = 0;
  std::vector<LatticeStep> best_path;
  std::optional<LatticeTrajectory> best;
  std::string last_failure;

  while (true) {
    // improvePath: expand until the best goal's g is no more than the smallest f in OPEN.
    while (!open.empty()) {
      if ((expansions & 15u) == 0 && termination.shouldStop(expansions, false)) {
        stopped = true;
        break;
      }
      const QueueEntry top = open.top();
      if (top.g != nodes[top.node].g || nodes[top.node].closed_round == round) {
        open.pop();
        continue;
      }
      if (best_goal_g <= top.f) break;
      open.pop();
      const std::int32_t current = top.node;
      nodes[current].closed_round = round;
      const LatticeState s = nodes[current].state;
      const double g = nodes[current].g;
      const std::uint64_t s_key = graph.key(s);
      ++expansions;
      const int edges = graph.edgeCount(s);
      for (int e = 0; e < edges; ++e) {
        const LatticeState t = graph.target(s, e);
        if (!graph.onLattice(t)) continue;
        const detail::CachedEdge& edge = cache.get(s, s_key, e, stats, nullptr);
        if (!std::isfinite(edge.cost)) continue;
        const double g2 = g + edge.cost;
        if (g2 >= best_goal_g) continue;  // cannot lead to a better path (h >= 0)
        const std::int32_t next = detail::findOrAddNode(index, nodes, graph.key(t), t);
        SearchNode& m = nodes[next];
        if (!(g2 < m.g)) continue;
        m.g = g2;
        m.parent = current;
        m.edge = e;
        ++stats.generated;
        if (graph.inGoal(t)) {
          if (g2 < best_goal_g) {
            best_goal_g = g2;
            best_goal = next;
            if (termination.stopsAtFirstSolution()) break;
          }
          continue;
        }
        if (m.closed_round == round) {
          if (!m.in_incons) {
            m.in_incons = true;
            incons.push_back(next);
          }
        } else {
          open.push({g2 + epsilon * graph.heuristic(t), g2, next});
        }
      }
      if (best_goal >= 0 && termination.stopsAtFirstSolution()) break;
    }
    ++stats.rounds;
    if (!stopped) stats.final_epsilon = epsilon;
    if (best_goal >= 0 && best_goal_g < published_g) {
      published_g = best_goal_g;
      std::vector<LatticeStep> path = detail::reconstructPath(nodes, best_goal);
      std::string why;
      std::optional<LatticeTrajectory> trajectory = graph.trajectory(path, &why);
      if (trajectory && (!best || trajectory->duration < best->duration)) {
        const double now = millisecondsSince(started);
        if (!result.first_solution_ms) {
          result.first_solution_ms = now;
          result.first_solution_cost_s = trajectory->duration;
        }
        result.cost_history.push_back({now, trajectory->duration});
        best = std::move(trajectory);
        best_path = std::move(path);
      } else if (!trajectory) {
        last_failure = why;
      }
    }
    if (!stopped && epsilon <= 1.0 && !(best_goal >= 0 && termination.stopsAtFirstSolution())) {
      proven = true;
    }
    if (stopped || !anytime || epsilon <= 1.0 || termination.timeUp() ||
        (best && termination.stopsAtFirstSolution())) {
      break;
    }
    if (open.empty() && incons.empty() && best_goal < 0) break;
    // Next round: a smaller epsilon; OPEN = OPEN u INCONS with the new priorities.
    epsilon = std::max(1.0, epsilon - step);
    ++round;
    std::vector<std::int32_t> members;
    members.reserve(open.size() + incons.size());
    while (!open.empty()) {
      const QueueEntry entry = open.top();
      open.pop();
      if (entry.g == nodes[entry.node].g && nodes[entry.node].closed_round != round - 1) {
        members.push_back(entry.node);
      }
    }
    for (std::int32_t n : incons) {
      nodes[n].in_incons = false;
      members.push_back(n);
    }
    incons.clear();
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    std::vector<QueueEntry> entries;
    entries.reserve(members.size());
    for (std::int32_t n : members) {
      entries.push_back({nodes[n].g + epsilon * graph.heuristic(nodes[n].state), nodes[n].g, n});
    }
    open = detail::OpenList(detail::QueueOrder(), std::move(entries));
  }

  stats.expansions = expansions;
  result.nodes = nodes.size();
  result.statistics.iterations = expansions;
  result.statistics.attempts = stats.edge_evaluations;
  result.statistics.trapped = stats.invalid_edges;
  result.statistics.improvements = result.cost_history.size();
  if (best) {
    result.status = PlanStatus::kSolved;
    result.best_cost_s = best->duration;
    result.trajectory = best->trajectory;
    result.length_m = best->length;
    PlanSolution solution;
    solution.trajectory = std::move(best->trajectory);
    solution.cost_s = best->duration;
    solution.search_cost_s = best->cost;
    solution.length_m = best->length;
    solution.proven_optimal = proven;
    solution.found_ms = result.cost_history.back().time_ms;
    result.solutions.push_back(std::move(solution));
  } else if (!last_failure.empty()) {
    result.reason = "the path found has no trajectory: " + last_failure;
  } else if (stopped || termination.timeUp()) {
    std::ostringstream text;
    text << "no path within the termination condition (" << expansions << " expansions)";
    result.reason = text.str();
  } else {
    result.reason = detail::exhaustedLatticeReason(graph, nodes.size());
  }
  return finish(result);
}

}  // namespace terratraj::search
