#include "lattice_search_core.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace terratraj::search::detail {

const CachedEdge& EdgeCache::get(const LatticeState& s, std::uint64_t state_key, int e,
                                 SearchStatistics& stats, const ReferenceFramesAdapter* frames) {
  const std::uint64_t key = (state_key << 10) | static_cast<std::uint64_t>(e);
  auto [entry, inserted] = table_.insert(key);
  if (!inserted) {
    ++stats.cache_hits;
    return *entry;
  }
  ++stats.edge_evaluations;
  const EdgeEvaluation evaluation = graph_->evaluate(s, e);
  entry->status = static_cast<std::uint8_t>(evaluation.status);
  if (evaluation.status != EdgeStatus::kValid) {
    ++stats.invalid_edges;
    entry->cost = std::numeric_limits<double>::infinity();
    return *entry;
  }
  entry->cost = evaluation.cost;
  if (frames != nullptr) {
    graph_->edgePoints(s, e, points_);
    scratch_.clear();  // keeps its capacity
    frames->crossings(points_, scratch_);
    entry->crossings_begin = static_cast<std::uint32_t>(crossings_.size());
    entry->crossings_count = static_cast<std::uint16_t>(scratch_.size());
    for (const FrameCrossing& c : scratch_.crossings()) crossings_.push_back(c);
  }
  return *entry;
}

std::vector<LatticeStep> reconstructPath(const std::vector<SearchNode>& nodes, std::int32_t node) {
  std::vector<LatticeStep> path;
  while (node >= 0 && nodes[node].parent >= 0) {
    const SearchNode& n = nodes[node];
    path.push_back({nodes[n.parent].state, n.edge});
    node = n.parent;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

std::string exhaustedLatticeReason(const LatticeGraph& graph, std::size_t states) {
  std::ostringstream text;
  const LatticeSpec& lattice = graph.lattice();
  text << "no path on this lattice: the search exhausted every state its primitives reach from "
          "the start ("
       << states << " states; " << graph.primitives().size() << " primitives at "
       << graph.primitives().generation.speed << " m/s, spacing " << lattice.resolution << " m, "
       << lattice.heading_count
       << " headings). This is a limit of the lattice, not a proof that the goal is "
          "unreachable: try planner.kind prm, a finer planner.lattice_resolution_m, more "
          "planner.heading_count, or larger goal tolerances";
  return text.str();
}

PlanSolution latticeSolution(LatticeTrajectory&& trajectory, double found_ms) {
  PlanSolution solution;
  solution.trajectory = std::move(trajectory.trajectory);
  solution.cost_s = trajectory.duration;
  solution.search_cost_s = trajectory.cost;
  solution.length_m = trajectory.length;
  solution.found_ms = found_ms;
  return solution;
}

void recordSearchCounts(std::size_t expansions, std::size_t nodes, PlanResult& result) {
  result.search.expansions = expansions;
  result.nodes = nodes;
  result.statistics.iterations = expansions;
  result.statistics.attempts = result.search.edge_evaluations;
  result.statistics.trapped = result.search.invalid_edges;
}

std::string noPathReason(const LatticeGraph& graph, const std::string& last_failure, bool exhausted,
                         std::size_t expansions, std::size_t nodes) {
  if (!last_failure.empty()) return "the paths found have no trajectory: " + last_failure;
  if (exhausted) return exhaustedLatticeReason(graph, nodes);
  std::ostringstream text;
  text << "no path within the termination condition (" << expansions << " expansions)";
  return text.str();
}

}  // namespace terratraj::search::detail
