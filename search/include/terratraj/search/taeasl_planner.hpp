#pragma once
// TaeaslPlanner: the topology-aware lattice search (TAEASL, Menon, Damm & Howard, 002_... II-III)
// over a LatticeGraph: several solutions, each the cheapest found in its homotopy class.
//
// Obstacle clusters of the lethal layer get reference frames (ReferenceFrames; docs/homotopy.md).
// A search node is a (lattice state, homotopy class) pair; its class is the signature of the
// frames its path crossed. One open list per class, created when a node first enters the class;
// expansions alternate round-robin across the non-empty lists. A goal state reached in a class
// is that class's solution candidate (replaced only by a cheaper one). Where the paper closes a
// class at its first solution, this implementation keeps every list as a frontier from which
// paths branch into other classes and instead drops a node once its g + h reaches the cost of
// the homotopy_classes-th cheapest candidate (it can improve none of the wanted classes). A node
// reached again with a lower cost is re-opened, so when the lists run empty each class's
// candidate is the cheapest path of that class on the lattice (signatures longer than
// max_signature_length excluded). docs/lattice.md explains why.
//
// Proof of optimality within a class (heuristic weight 1): a candidate of cost C is final when
// C <= min (g + h) over every open list (the heuristic is consistent, so no later path into the
// class can be cheaper); once `homotopy_classes` candidates are final they are the cheapest
// classes and the search stops. Otherwise it stops when the lists are empty or at the
// termination condition, returning the cheapest `homotopy_classes` candidates found.

#include <cstddef>

#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/planner.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/search/termination_condition.hpp"

namespace terratraj::search {

/// Where the reference frames radiate from.
enum class FrameAnchor {
  kMapCenter,  ///< the centre of the map (002_...)
  kStart,      ///< the robot's position (the start)
  kMidpoint,   ///< halfway between start and goal
};

/// "map_center", "start", "midpoint".
const char* frameAnchorName(FrameAnchor anchor);

/// Where `anchor` lies for `problem` [m, local]: the map's centre, the start, or halfway between
/// the start and the goal's centre.
Eigen::Vector2d frameAnchorPosition(FrameAnchor anchor, const PlanningProblem& problem);

/// The reference frames TAEASL names homotopy classes by on `problem`'s map: the obstacle
/// clusters of its lethal layer within `frame_radius` [m] of the anchor's position. Build them
/// once and hand them to TaeaslPlanner and to the refiner, so that both name the same classes.
ReferenceFrames taeaslReferenceFrames(const PlanningProblem& problem, FrameAnchor anchor,
                                      double frame_radius);

/// Settings of a TaeaslPlanner.
struct TaeaslOptions {
  int homotopy_classes = 3;    ///< most solutions returned, >= 1
  double frame_radius = 10.0;  ///< clusters within this distance of the anchor get frames [m]
  FrameAnchor anchor = FrameAnchor::kMapCenter;
  double heuristic_weight = 1.0;  ///< f = g + w h, >= 1 (> 1: faster, no optimality proof)
  /// Longest signature a node may carry (winding bound); <= 0: 2 x frames + 2.
  int max_signature_length = 0;
};

/// TAEASL on one graph. The graph must outlive the planner.
class TaeaslPlanner final : public Planner {
 public:
  /// Builds the obstacle clusters and reference frames of the graph's map (lethal layer) with
  /// options.anchor and options.frame_radius (taeaslReferenceFrames).
  TaeaslPlanner(const LatticeGraph& graph, const TaeaslOptions& options = {});
  /// With frames built already (taeaslReferenceFrames with options.anchor and
  /// options.frame_radius on the graph's problem).
  TaeaslPlanner(const LatticeGraph& graph, ReferenceFrames frames, const TaeaslOptions& options);

  /// Searches (the termination condition's iteration budget counts expansions). kSolved with
  /// PlanResult::solutions holding up to homotopy_classes solutions in distinct classes, best
  /// first, each with its signature; kNoSolution with a reason otherwise. Never throws (except
  /// std::bad_alloc).
  PlanResult solve(TerminationCondition termination) override;

  /// "taeasl".
  const char* name() const override { return "taeasl"; }
  /// Nothing to forget: every solve() searches afresh (the frames stay: they are the problem's).
  void clear() override {}

  /// The frames in use (their indices name the signatures' letters).
  const ReferenceFrames& frames() const { return frames_; }
  /// The anchor's position [m, local].
  const Eigen::Vector2d& anchorPosition() const { return anchor_; }
  /// The signature length bound in use.
  int maxSignatureLength() const { return max_signature_length_; }
  const TaeaslOptions& options() const { return options_; }

 private:
  const LatticeGraph* graph_;
  TaeaslOptions options_;
  Eigen::Vector2d anchor_ = Eigen::Vector2d::Zero();
  ReferenceFrames frames_;
  int max_signature_length_ = 2;
};

}  // namespace terratraj::search
