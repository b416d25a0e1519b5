#include "terratraj/search/lattice_planner.hpp"

#include "terratraj/search/plan_verdict.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "lattice_search_core.hpp"

namespace terratraj::search {
namespace {

using detail::millisecondsSince;
using detail::QueueEntry;
using detail::SearchNode;

// The ARA* search of one solve() (A* is one round at epsilon 1): the node table, OPEN, INCONS
// and the best goal node.
class AraStarSearch {
 public:
  AraStarSearch(const LatticeGraph& graph, double epsilon, SearchStatistics& stats)
      : graph_(graph), cache_(graph), epsilon_(epsilon), stats_(stats) {
    nodes_.reserve(1 << 15);
    const LatticeState start = graph.start();
    *index_.insert(graph.key(start)).first = 0;
    nodes_.push_back({});
    nodes_[0].state = start;
    nodes_[0].g = 0.0;
    open_.push({epsilon_ * graph.heuristic(start), 0.0, 0});
  }

  // improvePath: expands until the best goal's g is no more than the smallest f in OPEN (or
  // the first goal, when the condition stops at the first solution). False when the
  // termination condition stopped it.
  bool improvePath(TerminationCondition& termination) {
    while (!open_.empty()) {
      if ((expansions_ & 15u) == 0 &&
          termination.shouldStop(expansions_ - call_expansions_, false)) {
        return false;
      }
      const QueueEntry top = open_.top();
      if (top.g != nodes_[top.node].g || nodes_[top.node].closed_round == round_) {
        open_.pop();
        continue;
      }
      if (best_goal_g_ <= top.f) break;
      open_.pop();
      expand(top.node, termination.stopsAtFirstSolution());
      if (best_goal_ >= 0 && termination.stopsAtFirstSolution()) break;
    }
    return true;
  }

  // The path to the best goal when it is cheaper than the last one returned here.
  std::optional<std::vector<LatticeStep>> improvedPath() {
    if (best_goal_ < 0 || !(best_goal_g_ < published_g_)) return std::nullopt;
    published_g_ = best_goal_g_;
    return detail::reconstructPath(nodes_, best_goal_);
  }

  // Next round at `epsilon`: OPEN = OPEN u INCONS with the new priorities.
  void startRound(double epsilon) {
    epsilon_ = epsilon;
    ++round_;
    std::vector<std::int32_t> members;
    members.reserve(open_.size() + incons_.size());
    while (!open_.empty()) {
      const QueueEntry entry = open_.top();
      open_.pop();
      if (entry.g == nodes_[entry.node].g && nodes_[entry.node].closed_round != round_ - 1) {
        members.push_back(entry.node);
      }
    }
    for (std::int32_t n : incons_) {
      nodes_[n].in_incons = false;
      members.push_back(n);
    }
    incons_.clear();
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    std::vector<QueueEntry> entries;
    entries.reserve(members.size());
    for (std::int32_t n : members) {
      entries.push_back(
          {nodes_[n].g + epsilon_ * graph_.heuristic(nodes_[n].state), nodes_[n].g, n});
    }
    open_ = detail::OpenList(detail::QueueOrder(), std::move(entries));
  }

  // A new solve() call: its iteration budget counts expansions from here.
  void beginCall() { call_expansions_ = expansions_; }

  bool foundGoal() const { return best_goal_ >= 0; }
  // Nothing left to search: OPEN and INCONS empty and no goal reached.
  bool idle() const { return open_.empty() && incons_.empty() && best_goal_ < 0; }
  double epsilon() const { return epsilon_; }
  std::size_t expansions() const { return expansions_; }
  std::size_t nodeCount() const { return nodes_.size(); }

 private:
  // Closes `current` in this round and relaxes its successors.
  void expand(std::int32_t current, bool stop_at_first) {
    nodes_[current].closed_round = round_;
    const LatticeState s = nodes_[current].state;
    const double g = nodes_[current].g;
    ++expansions_;
    detail::forEachValidEdge(graph_, cache_, s, stats_, nullptr,
                             [&](int e, const LatticeState& t, const detail::CachedEdge& edge) {
                               return relax(current, g + edge.cost, e, t, stop_at_first);
                             });
  }

  // Offers `t` the cost `g2` through edge `e` of `current`; false to stop the expansion (the
  // first goal, when the condition stops there).
  bool relax(std::int32_t current, double g2, int e, const LatticeState& t, bool stop_at_first) {
    if (g2 >= best_goal_g_) return true;  // cannot lead to a better path (h >= 0)
    const std::int32_t next = detail::findOrAddNode(index_, nodes_, graph_.key(t), t);
    SearchNode& m = nodes_[next];
    if (!(g2 < m.g)) return true;
    m.g = g2;
    m.parent = current;
    m.edge = e;
    ++stats_.generated;
    if (graph_.inGoal(t)) {
      best_goal_g_ = g2;
      best_goal_ = next;
      return !stop_at_first;
    }
    if (m.closed_round == round_) {
      if (!m.in_incons) {
        m.in_incons = true;
        incons_.push_back(next);
      }
    } else {
      open_.push({g2 + epsilon_ * graph_.heuristic(t), g2, next});
    }
    return true;
  }

  const LatticeGraph& graph_;
  detail::EdgeCache cache_;
  double epsilon_;
  SearchStatistics& stats_;
  std::vector<SearchNode> nodes_;
  detail::FlatHashMap<std::int32_t> index_{1 << 15};
  detail::OpenList open_;
  std::vector<std::int32_t> incons_;
  std::int32_t best_goal_ = -1;
  double best_goal_g_ = std::numeric_limits<double>::infinity();
  double published_g_ = std::numeric_limits<double>::infinity();
  std::uint32_t round_ = 1;
  std::size_t expansions_ = 0;
  std::size_t call_expansions_ = 0;  // expansions_ when the current solve() began
};

}  // namespace

// What solve() calls carry over (clear() drops it): the search with its node table, OPEN and
// INCONS, the round's epsilon, the best trajectory and the counts.
struct LatticePlanner::Progress {
  Progress(const LatticeGraph& graph, double epsilon_in)
      : search(graph, epsilon_in, stats), epsilon(epsilon_in) {
    stats.rounds = 1;
  }
  // The next round at the next epsilon (OPEN u INCONS re-keyed).
  void nextRound(double step) {
    epsilon = std::max(1.0, epsilon - step);
    search.startRound(epsilon);
    round_done = false;
    ++stats.rounds;
  }

  SearchStatistics stats;  // before `search`, which counts into it; rounds = rounds begun
  AraStarSearch search;
  double epsilon;
  bool round_done = false;  // the round at `epsilon` finished (the next call starts the next)
  bool finished = false;    // the search ended (optimal round done, or nothing left)
  bool proven = false;
  std::optional<LatticeTrajectory> best;
  std::string last_failure;
  std::vector<CostSample> cost_history;
  std::optional<double> first_solution_ms;
  double first_solution_cost_s = std::numeric_limits<double>::infinity();
  double planned_ms = 0.0;  // planning time of the earlier calls [ms]
  bool exhausted = false;   // OPEN emptied without a goal
};

const char* latticeAlgorithmName(LatticeAlgorithm algorithm) {
  return algorithm == LatticeAlgorithm::kAStar ? "astar" : "arastar";
}

LatticePlanner::LatticePlanner(const LatticeGraph& graph, const LatticePlannerOptions& options)
    : graph_(&graph), options_(options) {}

LatticePlanner::~LatticePlanner() = default;

void LatticePlanner::clear() { progress_.reset(); }

PlanResult LatticePlanner::solve(TerminationCondition termination) {
  const auto started = std::chrono::steady_clock::now();
  termination.start();
  PlanResult result;
  const LatticeGraph& graph = *graph_;
  // Times run in planning time summed over the calls [ms].
  const double planned_before_ms = progress_ ? progress_->planned_ms : 0.0;
  const auto now_ms = [&] { return planned_before_ms + millisecondsSince(started); };
  const auto finish = [&](PlanResult& r) -> PlanResult {
    applyPlanVerdict(graph.problem(), r);
    r.planning_time_ms = now_ms();
    if (progress_) progress_->planned_ms = r.planning_time_ms;
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
  const double step = options_.epsilon_step > 0.0 ? options_.epsilon_step : 0.5;
  if (!progress_) {
    progress_ =
        std::make_unique<Progress>(graph, anytime ? std::max(1.0, options_.initial_epsilon) : 1.0);
  }
  Progress& p = *progress_;
  bool stopped = false;
  if (!p.finished) {
    p.search.beginCall();
    if (p.round_done) p.nextRound(step);  // the previous call finished a round
    while (true) {
      stopped = !p.search.improvePath(termination);
      // A round stopped at its first goal (stopsAtFirstSolution) is resumed, not finished.
      p.round_done = !stopped && !termination.stopsAtFirstSolution();
      if (!stopped) p.stats.final_epsilon = p.epsilon;
      if (std::optional<std::vector<LatticeStep>> path = p.search.improvedPath()) {
        Expected<LatticeTrajectory> trajectory = graph.trajectory(*path);
        if (trajectory && (!p.best || trajectory->duration < p.best->duration)) {
          const double now = now_ms();
          if (!p.first_solution_ms) {
            p.first_solution_ms = now;
            p.first_solution_cost_s = trajectory->duration;
          }
          p.cost_history.push_back({now, trajectory->duration});
          p.best = std::move(*trajectory);
        } else if (!trajectory) {
          p.last_failure = trajectory.reason();
        }
      }
      if (p.round_done && p.epsilon <= 1.0) p.proven = true;
      if (p.search.idle()) p.exhausted = true;
      p.finished = p.exhausted || (p.round_done && (!anytime || p.epsilon <= 1.0));
      if (p.finished || stopped || termination.timeUp() ||
          (p.best && termination.stopsAtFirstSolution())) {
        break;
      }
      p.nextRound(step);
    }
  }

  result.search = p.stats;
  result.first_solution_ms = p.first_solution_ms;
  result.first_solution_cost_s = p.first_solution_cost_s;
  result.cost_history = p.cost_history;
  detail::recordSearchCounts(p.search.expansions(), p.search.nodeCount(), result);
  result.statistics.improvements = result.cost_history.size();
  if (p.best) {
    result.status = PlanStatus::kSolved;  // applyPlanVerdict() fills the summary
    PlanSolution solution =
        detail::latticeSolution(LatticeTrajectory(*p.best), result.cost_history.back().time_ms);
    solution.proven_optimal = p.proven;
    result.solutions.push_back(std::move(solution));
  } else {
    result.reason = detail::noPathReason(graph, p.last_failure, p.exhausted, p.search.expansions(),
                                         p.search.nodeCount());
  }
  return finish(result);
}

}  // namespace terratraj::search
