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
using Clock = std::chrono::steady_clock;

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

// The multi-class search of one solve(): the node table (a node is a lattice state in one
// homotopy class), one open list per class visited round-robin, and the pruning bound (the
// `wanted`-th cheapest candidate).
class TaeaslSearch {
 public:
  TaeaslSearch(const LatticeGraph& graph, const ReferenceFrames& frames, double weight, int wanted,
               int max_signature_length, SearchStatistics& stats)
      : graph_(graph),
        frames_(frames),
        adapter_(frames),
        cache_(graph),
        w_(weight),
        wanted_(wanted),
        max_signature_length_(max_signature_length),
        stats_(stats) {
    nodes_.reserve(1 << 15);
    const LatticeState start = graph.start();
    const std::int32_t root_class = classIndex(HomotopySignature());
    *index_.insert(nodeKey(start, root_class)).first = 0;
    nodes_.push_back({});
    nodes_[0].state = start;
    nodes_[0].g = 0.0;
    nodes_[0].klass = root_class;
    classes_[root_class].open.push({w_ * graph.heuristic(start), 0.0, 0});
    activate(root_class);
  }

  // Expands until `wanted` candidates are proven (weight 1), every list is empty, or the
  // termination condition stops it (once a class has reached the goal, at kSearchShare of the
  // time limit: the rest builds and checks the trajectories within the limit).
  void run(TerminationCondition& termination, Clock::time_point started, PlanResult& result) {
    constexpr double kSearchShare = 0.85;
    const double search_limit_s = kSearchShare * termination.timeLimitSeconds();
    const bool provable = w_ == 1.0;
    while (true) {
      if ((expansions_ & 15u) == 0 &&
          (termination.shouldStop(expansions_, false) ||
           (result.first_solution_ms && termination.elapsedSeconds() >= search_limit_s))) {
        stopped_ = true;
        break;
      }
      if (provable && expansions_ % kConfirmEvery == 0 && expansions_ > 0 && confirm() >= wanted_) {
        break;
      }
      const std::int32_t klass = nextClass();
      if (klass < 0) {
        exhausted_ = true;
        break;
      }
      expandTop(klass, started, result);
    }
    if (provable && (exhausted_ || !stopped_)) confirm();
  }

  // The classes that reached the goal, cheapest first (ties by signature).
  std::vector<std::int32_t> foundClasses() const {
    std::vector<std::int32_t> found;
    for (std::int32_t c = 0; c < static_cast<std::int32_t>(classes_.size()); ++c) {
      if (classes_[c].best_goal >= 0) found.push_back(c);
    }
    std::sort(found.begin(), found.end(), [&](std::int32_t a, std::int32_t b) {
      return classes_[a].best_goal_g < classes_[b].best_goal_g ||
             (classes_[a].best_goal_g == classes_[b].best_goal_g &&
              classes_[a].signature < classes_[b].signature);
    });
    return found;
  }

  const HomotopyClass& homotopyClass(std::int32_t c) const { return classes_[c]; }
  const std::vector<SearchNode>& nodes() const { return nodes_; }
  std::size_t expansions() const { return expansions_; }
  std::size_t classCount() const { return classes_.size(); }
  bool exhausted() const { return exhausted_; }

 private:
  std::int32_t classIndex(const HomotopySignature& signature) {
    const auto [it, inserted] =
        class_of_.emplace(signature, static_cast<std::int32_t>(classes_.size()));
    if (inserted) {
      classes_.emplace_back();
      classes_.back().signature = signature;
    }
    return it->second;
  }

  std::uint64_t nodeKey(const LatticeState& s, std::int32_t klass) const {
    return (static_cast<std::uint64_t>(klass) << kStateKeyBits) | graph_.key(s);
  }

  void activate(std::int32_t klass) {
    if (!classes_[klass].active) {
      classes_[klass].active = true;
      active_.push_back(klass);
    }
  }

  // Drops stale entries from the top of a class's list.
  void clean(HomotopyClass& c) const {
    while (!c.open.empty() && c.open.top().g != nodes_[c.open.top().node].g) c.open.pop();
  }

  // Marks as final every candidate no open node can beat; returns how many are final.
  int confirm() {
    double lower = std::numeric_limits<double>::infinity();
    for (HomotopyClass& c : classes_) {
      clean(c);
      if (!c.open.empty()) lower = std::min(lower, c.open.top().f);
    }
    int final_count = 0;
    for (HomotopyClass& c : classes_) {
      if (c.best_goal >= 0 && c.best_goal_g <= lower) c.final = true;
      final_count += c.final ? 1 : 0;
    }
    return final_count;
  }

  // The wanted-th cheapest candidate's cost: a node with g + h at least this cannot lead to
  // one of the `wanted` cheapest classes. +inf while fewer classes have a candidate.
  double kthCandidateCost() {
    candidate_costs_.clear();
    for (const HomotopyClass& c : classes_) {
      if (c.best_goal >= 0) candidate_costs_.push_back(c.best_goal_g);
    }
    if (static_cast<int>(candidate_costs_.size()) < wanted_) {
      return std::numeric_limits<double>::infinity();
    }
    std::nth_element(candidate_costs_.begin(), candidate_costs_.begin() + (wanted_ - 1),
                     candidate_costs_.end());
    return candidate_costs_[wanted_ - 1];
  }

  // The next class in turn with work; -1 when every list is empty.
  std::int32_t nextClass() {
    while (!active_.empty()) {
      if (cursor_ >= active_.size()) cursor_ = 0;
      HomotopyClass& c = classes_[active_[cursor_]];
      clean(c);
      if (c.open.empty()) {
        c.active = false;
        active_[cursor_] = active_.back();
        active_.pop_back();
        continue;
      }
      return active_[cursor_++];
    }
    return -1;
  }

  // The class a successor of a node in `klass` enters over `edge`; -1 when its signature grows
  // past max_signature_length (pruned).
  std::int32_t successorClass(std::int32_t klass, const detail::CachedEdge& edge) {
    if (edge.crossings_count == 0) return klass;
    signature_ = classes_[klass].signature;
    const std::vector<FrameCrossing>& all = cache_.crossings();
    for (std::uint32_t k = 0; k < edge.crossings_count; ++k) {
      signature_.append(all[edge.crossings_begin + k]);
    }
    if (static_cast<int>(signature_.size()) > max_signature_length_) {
      ++stats_.pruned_signatures;
      return -1;
    }
    return classIndex(signature_);
  }

  // The class of a path in `klass` that ends at goal state `t`, closed by the segment to the exact
  // goal (ReferenceFrames::signatureBetween: what a refinement, which ends there, is compared
  // with; two ends of one route in the goal region on either side of a frame are one class);
  // -1 when its signature grows past max_signature_length (pruned).
  std::int32_t closedClass(std::int32_t klass, const LatticeState& t) {
    signature_ = classes_[klass].signature;
    frames_.appendCrossings(graph_.position(t), graph_.problem().goal.position, signature_);
    if (signature_ == classes_[klass].signature) return klass;
    if (static_cast<int>(signature_.size()) > max_signature_length_) {
      ++stats_.pruned_signatures;
      return -1;
    }
    return classIndex(signature_);
  }

  // Pops the top of `klass`'s list and relaxes its successors.
  void expandTop(std::int32_t klass, Clock::time_point started, PlanResult& result) {
    const QueueEntry top = classes_[klass].open.top();
    classes_[klass].open.pop();
    const std::int32_t current = top.node;
    const LatticeState s = nodes_[current].state;
    const double g = nodes_[current].g;
    if (g + graph_.heuristic(s) >= bound_) return;  // cannot reach a wanted class
    ++expansions_;
    detail::forEachValidEdge(graph_, cache_, s, stats_, &adapter_,
                             [&](int e, const LatticeState& t, const detail::CachedEdge& edge) {
                               const std::int32_t next_class = successorClass(klass, edge);
                               if (next_class >= 0)
                                 relax(current, g + edge.cost, e, t, next_class, started, result);
                               return true;
                             });
  }

  // Offers `t` in class `next_class` the cost `g2` through edge `e` of `current`.
  void relax(std::int32_t current, double g2, int e, const LatticeState& t, std::int32_t next_class,
             Clock::time_point started, PlanResult& result) {
    const bool goal = graph_.inGoal(t);
    if (goal) next_class = closedClass(next_class, t);
    if (next_class < 0) return;
    if (goal ? g2 >= classes_[next_class].best_goal_g : g2 + graph_.heuristic(t) >= bound_) {
      return;
    }
    const std::int32_t next =
        detail::findOrAddNode(index_, nodes_, nodeKey(t, next_class), t, next_class);
    SearchNode& m = nodes_[next];
    if (!(g2 < m.g)) return;
    m.g = g2;
    m.parent = current;
    m.edge = e;
    ++stats_.generated;
    HomotopyClass& c = classes_[next_class];
    if (goal) {
      c.best_goal = next;
      c.best_goal_g = g2;
      c.found_ms = millisecondsSince(started);
      if (!result.first_solution_ms) result.first_solution_ms = c.found_ms;
      bound_ = kthCandidateCost();
      return;
    }
    c.open.push({g2 + w_ * graph_.heuristic(t), g2, next});
    activate(next_class);
  }

  const LatticeGraph& graph_;
  const ReferenceFrames& frames_;
  const FramesAdapter adapter_;
  detail::EdgeCache cache_;
  double w_;
  int wanted_;
  int max_signature_length_;
  SearchStatistics& stats_;
  std::vector<SearchNode> nodes_;
  detail::FlatHashMap<std::int32_t> index_{1 << 15};
  std::vector<HomotopyClass> classes_;
  std::unordered_map<HomotopySignature, std::int32_t, HomotopySignatureHash> class_of_;
  std::vector<std::int32_t> active_;
  std::size_t cursor_ = 0;
  double bound_ = std::numeric_limits<double>::infinity();
  std::vector<double> candidate_costs_;
  HomotopySignature signature_;  // scratch for successorClass()
  std::size_t expansions_ = 0;
  bool stopped_ = false;
  bool exhausted_ = false;
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

Eigen::Vector2d frameAnchorPosition(FrameAnchor anchor, const PlanningProblem& problem) {
  const terrain::GridGeometry& geometry = problem.map->geometry();
  switch (anchor) {
    case FrameAnchor::kStart:
      return problem.start.position;
    case FrameAnchor::kMidpoint:
      return 0.5 * (problem.start.position + problem.goal.position);
    case FrameAnchor::kMapCenter:
      break;
  }
  return {0.5 * geometry.width(), 0.5 * geometry.height()};
}

ReferenceFrames taeaslReferenceFrames(const PlanningProblem& problem, FrameAnchor anchor,
                                      double frame_radius) {
  ReferenceFrameOptions options;
  options.anchor = frameAnchorPosition(anchor, problem);
  options.frame_radius = frame_radius;
  return ReferenceFrames::build(*problem.map, terrain::findObstacleClusters(*problem.map), options);
}

TaeaslPlanner::TaeaslPlanner(const LatticeGraph& graph, const TaeaslOptions& options)
    : TaeaslPlanner(graph,
                    taeaslReferenceFrames(graph.problem(), options.anchor, options.frame_radius),
                    options) {}

TaeaslPlanner::TaeaslPlanner(const LatticeGraph& graph, ReferenceFrames frames,
                             const TaeaslOptions& options)
    : graph_(&graph),
      options_(options),
      anchor_(frameAnchorPosition(options.anchor, graph.problem())),
      frames_(std::move(frames)) {
  max_signature_length_ = options.max_signature_length > 0
                              ? options.max_signature_length
                              : 2 * static_cast<int>(frames_.size()) + 2;
}

PlanResult TaeaslPlanner::solve(TerminationCondition termination) {
  const auto started = Clock::now();
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
  TaeaslSearch search(graph, frames_, w, wanted, max_signature_length_, stats);
  search.run(termination, started, result);

  // The cheapest candidates, one per class.
  const std::vector<std::int32_t> found = search.foundClasses();
  std::string last_failure;
  const models::TrajectoryRequirements requirements = requirementsOf(graph.problem());
  std::size_t built = 0;
  for (std::int32_t c : found) {
    if (static_cast<int>(result.solutions.size()) >= options_.homotopy_classes) break;
    // Past the time limit only the best class is still built: the limit holds.
    if (!result.solutions.empty() && termination.timeUp()) break;
    const HomotopyClass& k = search.homotopyClass(c);
    Expected<LatticeTrajectory> trajectory =
        graph.trajectory(detail::reconstructPath(search.nodes(), k.best_goal));
    ++built;
    if (!trajectory) {
      last_failure = k.signature.toString() + ": " + trajectory.reason();
      continue;
    }
    PlanSolution solution = detail::latticeSolution(std::move(*trajectory), k.found_ms);
    solution.homotopy = k.signature.toString();
    solution.proven_optimal = w == 1.0 && (k.final || search.exhausted());
    if (admitSolution(requirements, std::move(solution), result)) {
      result.cost_history.push_back({k.found_ms, result.solutions.back().cost_s});
    }
  }
  stats.classes_found = found.size();
  stats.classes_built = built;
  std::sort(result.cost_history.begin(), result.cost_history.end(),
            [](const CostSample& a, const CostSample& b) { return a.time_ms < b.time_ms; });
  stats.homotopy_classes = search.classCount();
  stats.final_epsilon = w;
  detail::recordSearchCounts(search.expansions(), search.nodes().size(), result);
  concludePlan(result);
  if (!result.solutions.empty()) {
    result.first_solution_cost_s = result.cost_history.front().cost_s;
  } else if (result.rejected.empty()) {  // else concludePlan() said why
    result.reason = detail::noPathReason(graph, last_failure, search.exhausted(),
                                         search.expansions(), search.nodes().size());
  }
  return finish(result);
}

}  // namespace terratraj::search
