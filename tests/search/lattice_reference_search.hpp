#pragma once
// Brute-force references for the lattice searches: Dijkstra over the lattice (optionally over
// lattice state x homotopy signature), with the searches' goal semantics (a goal state ends a
// path and is not expanded). Slow and simple on purpose: it shares no code with the planners
// beyond the graph itself.

#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <string>
#include <tuple>
#include <vector>

#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/reference_frames.hpp"

namespace terratraj::search::testing {

/// Cheapest cost to the goal region for every homotopy class whose best cost is at most the
/// `classes`-th cheapest class's (all classes when `frames` is null: one class ""), signatures
/// longer than max_length excluded; a path's class is its signature closed by the segment from
/// its goal state to the exact goal (ReferenceFrames::signatureBetween).
inline std::map<std::string, double> referenceCosts(const LatticeGraph& graph,
                                                    const ReferenceFrames* frames, int max_length,
                                                    int classes) {
  using Label = std::pair<std::uint64_t, std::string>;
  struct Item {
    double cost;
    LatticeState state;
    HomotopySignature signature;
    bool operator>(const Item& o) const { return cost > o.cost; }
  };
  std::map<Label, double> best;
  std::map<std::string, double> goal_costs;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  queue.push({0.0, graph.start(), HomotopySignature()});
  best[{graph.key(graph.start()), ""}] = 0.0;
  std::vector<Eigen::Vector2d> points;
  const auto threshold = [&]() {
    if (static_cast<int>(goal_costs.size()) < classes) {
      return std::numeric_limits<double>::infinity();
    }
    std::vector<double> costs;
    for (const auto& entry : goal_costs) costs.push_back(entry.second);
    std::sort(costs.begin(), costs.end());
    return costs[classes - 1];
  };
  while (!queue.empty()) {
    const Item item = queue.top();
    queue.pop();
    if (item.cost > best[{graph.key(item.state), item.signature.toString()}]) continue;
    if (item.cost > threshold()) break;
    for (int e = 0; e < graph.edgeCount(item.state); ++e) {
      const LatticeState t = graph.target(item.state, e);
      if (!graph.onLattice(t)) continue;
      const EdgeEvaluation evaluation = graph.evaluate(item.state, e);
      if (evaluation.status != EdgeStatus::kValid) continue;
      HomotopySignature signature = item.signature;
      if (frames != nullptr) {
        graph.edgePoints(item.state, e, points);
        for (std::size_t k = 1; k < points.size(); ++k) {
          frames->appendCrossings(points[k - 1], points[k], signature);
        }
        if (static_cast<int>(signature.size()) > max_length) continue;
      }
      const double cost = item.cost + evaluation.cost;
      const bool goal = graph.inGoal(t);
      if (goal && frames != nullptr) {  // closed at the exact goal
        frames->appendCrossings(graph.position(t), graph.problem().goal.position, signature);
        if (static_cast<int>(signature.size()) > max_length) continue;
      }
      const std::string name = signature.toString();
      if (goal) {
        auto [it, inserted] = goal_costs.emplace(name, cost);
        if (!inserted && cost < it->second) it->second = cost;
        continue;
      }
      const Label label{graph.key(t), name};
      auto found = best.find(label);
      if (found != best.end() && found->second <= cost) continue;
      best[label] = cost;
      queue.push({cost, t, signature});
    }
  }
  const double limit = threshold();
  std::map<std::string, double> out;
  for (const auto& [name, cost] : goal_costs) {
    if (cost <= limit) out[name] = cost;
  }
  return out;
}

}  // namespace terratraj::search::testing
