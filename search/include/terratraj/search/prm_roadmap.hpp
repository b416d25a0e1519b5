#pragma once
// The roadmap of the kinodynamic PRM: a tree in state x time rooted at the start (001_... IV:
// each node stores its accumulated time L(s0, s) and the edge that reached it).

#include <cstdint>
#include <vector>

#include "terratraj/search/extension_integrator.hpp"
#include "terratraj/search/planner_state.hpp"

namespace terratraj::search {

/// Parent id of the root.
inline constexpr std::int32_t kNoParent = -1;

/// One node: a state, its time from the start, and how it was reached from its parent.
struct PrmNode {
  PlannerState state;
  double cost = 0.0;                ///< L(s0, s): time from the start [s]
  std::int32_t parent = kNoParent;  ///< id of the parent node
  ExtensionRequest edge;            ///< the extension from the parent that reached it
  bool alive = true;                ///< false once pruned by branch and bound
};

/// Nodes by id (their index). Ids are stable; pruned nodes stay (as ancestors) but are dead.
class PrmRoadmap {
 public:
  /// Reserves room for `capacity` nodes.
  void reserve(std::size_t capacity) { nodes_.reserve(capacity); }
  /// Removes every node.
  void clear() { nodes_.clear(); }
  /// Adds a node; returns its id.
  std::int32_t add(const PrmNode& node);
  /// The node of an id in [0, size()); no bounds check.
  const PrmNode& node(std::int32_t id) const { return nodes_[static_cast<std::size_t>(id)]; }
  PrmNode& node(std::int32_t id) { return nodes_[static_cast<std::size_t>(id)]; }
  /// Number of nodes, dead ones included.
  std::size_t size() const { return nodes_.size(); }
  /// Every node, by id.
  const std::vector<PrmNode>& nodes() const { return nodes_; }
  /// Ids from the root to `id`, root first.
  std::vector<std::int32_t> pathTo(std::int32_t id) const;

 private:
  std::vector<PrmNode> nodes_;
};

}  // namespace terratraj::search
