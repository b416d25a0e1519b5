#pragma once
// Shared machinery of the lattice searches (internal): the node table, the edge cache, the
// priority-queue entries and path reconstruction.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <string>
#include <vector>

#include "flat_hash_map.hpp"
#include "terratraj/search/homotopy_signature.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/plan_result.hpp"

namespace terratraj::search::detail {

/// Most edges per state the caches can key (primitives per heading).
inline constexpr int kMaxEdgesPerState = 1024;

/// One search node: a lattice state (in one homotopy class for TAEASL).
struct SearchNode {
  LatticeState state;
  double g = std::numeric_limits<double>::infinity();
  std::int32_t parent = -1;        ///< node index, -1 for the start
  std::int32_t edge = -1;          ///< edge of the parent's state leading here
  std::int32_t klass = 0;          ///< homotopy class (TAEASL), 0 otherwise
  std::uint32_t closed_round = 0;  ///< round in which it was expanded (0 = never)
  bool in_incons = false;          ///< ARA*: waiting in INCONS
};

/// A priority-queue entry; stale when the node's g has changed since.
struct QueueEntry {
  double f;
  double g;
  std::int32_t node;
};

/// Smallest f first; ties: larger g first (deeper nodes).
struct QueueOrder {
  bool operator()(const QueueEntry& a, const QueueEntry& b) const {
    return a.f > b.f || (a.f == b.f && a.g < b.g);
  }
};

using OpenList = std::priority_queue<QueueEntry, std::vector<QueueEntry>, QueueOrder>;

/// Crossing computation for EdgeCache (TAEASL); null for the plain searches.
class ReferenceFramesAdapter {
 public:
  virtual ~ReferenceFramesAdapter() = default;
  /// Appends the crossings of the polyline to `signature`.
  virtual void crossings(const std::vector<Eigen::Vector2d>& points,
                         HomotopySignature& signature) const = 0;
};

/// A cached edge: its evaluation and (TAEASL) the frame crossings along it.
struct CachedEdge {
  double cost = 0.0;  ///< +inf when invalid
  std::uint32_t crossings_begin = 0;
  std::uint16_t crossings_count = 0;
  std::uint8_t status = 0;  ///< EdgeStatus
};

/// Edge evaluations memoised by (state, edge): ARA* re-expands states across rounds and TAEASL
/// expands one state in several classes.
class EdgeCache {
 public:
  explicit EdgeCache(const LatticeGraph& graph) : graph_(&graph) {}
  /// The evaluation of edge `e` of `s`, from the cache or the graph. `stats` counts both.
  const CachedEdge& get(const LatticeState& s, std::uint64_t state_key, int e,
                        SearchStatistics& stats, const ReferenceFramesAdapter* frames);
  /// The crossings of a cached edge.
  const std::vector<FrameCrossing>& crossings() const { return crossings_; }

 private:
  const LatticeGraph* graph_;
  FlatHashMap<CachedEdge> table_{1 << 14};
  std::vector<FrameCrossing> crossings_;
  std::vector<Eigen::Vector2d> points_;
  HomotopySignature scratch_;
};

/// Milliseconds since `start`.
inline double millisecondsSince(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

/// The node of `key` (state `state` in class `klass`), appended to `nodes` if new.
inline std::int32_t findOrAddNode(FlatHashMap<std::int32_t>& index, std::vector<SearchNode>& nodes,
                                  std::uint64_t key, const LatticeState& state,
                                  std::int32_t klass = 0) {
  const auto [slot, inserted] = index.insert(key);
  if (inserted) {
    *slot = static_cast<std::int32_t>(nodes.size());
    nodes.push_back({});
    nodes.back().state = state;
    nodes.back().klass = klass;
  }
  return *slot;
}

/// The relaxation step both searches share: calls visit(e, t, edge) for every edge `e` of `s`
/// whose target `t` stays on the lattice and whose evaluation (through `cache`, which counts in
/// `stats`; `frames` adds TAEASL's crossings, null otherwise) is valid. `visit` returns false
/// to stop early.
template <typename Visit>
void forEachValidEdge(const LatticeGraph& graph, EdgeCache& cache, const LatticeState& s,
                      SearchStatistics& stats, const ReferenceFramesAdapter* frames,
                      Visit&& visit) {
  const std::uint64_t key = graph.key(s);
  const int edges = graph.edgeCount(s);
  for (int e = 0; e < edges; ++e) {
    const LatticeState t = graph.target(s, e);
    if (!graph.onLattice(t)) continue;
    const CachedEdge& edge = cache.get(s, key, e, stats, frames);
    if (!std::isfinite(edge.cost)) continue;
    if (!visit(e, t, edge)) return;
  }
}

/// Why a lattice search that exhausted every reachable state found no path: not a proof that the
/// goal is unreachable, only that this lattice (its primitives, spacing, headings, speed) does
/// not reach it; names the settings to change.
std::string exhaustedLatticeReason(const LatticeGraph& graph, std::size_t states);

/// The path from the start to `node` as steps.
std::vector<LatticeStep> reconstructPath(const std::vector<SearchNode>& nodes, std::int32_t node);

/// A solution from a path's trajectory found at `found_ms` [ms] (homotopy and proven_optimal
/// are the caller's).
PlanSolution latticeSolution(LatticeTrajectory&& trajectory, double found_ms);

/// The counters every lattice search reports: expansions, nodes and the edge evaluations
/// (`result.search` already holds the cache's counts).
void recordSearchCounts(std::size_t expansions, std::size_t nodes, PlanResult& result);

/// Why a lattice search returns no solution: the paths it found have no trajectory
/// (`last_failure`, non-empty), every reachable state was expanded (`exhausted`:
/// exhaustedLatticeReason), or the termination condition stopped it first.
std::string noPathReason(const LatticeGraph& graph, const std::string& last_failure, bool exhausted,
                         std::size_t expansions, std::size_t nodes);

}  // namespace terratraj::search::detail
