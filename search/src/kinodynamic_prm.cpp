#include "terratraj/search/kinodynamic_prm.hpp"

#include "terratraj/search/plan_verdict.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace terratraj::search {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Bounds on delta_g as a fraction of the cell size: at most one cell (the lethal check of a
// segment looks at the cells next to its ends only), at least 1/20 of a cell.
constexpr double kMinDeltaGFraction = 0.05;
constexpr double kMaxDeltaGFraction = 1.0;
// Tries at rejection sampling inside the informed ellipse before falling back to the map.
constexpr int kInformedTries = 8;
// A goal connection may be this many times longer than the connection radius.
constexpr double kGoalConnectionLengthFactor = 3.0;
constexpr double kPi = 3.14159265358979323846;
// Approach points tried when a direct goal connection misses the goal heading: how many, how
// far behind the goal [m], and how far off its axis (fraction of the heading tolerance).
constexpr int kApproachTries = 3;
constexpr double kApproachDistanceMin = 1.5;
constexpr double kApproachDistanceMax = 8.0;
constexpr double kApproachAngleFraction = 0.8;

IntegrationSettings settingsFor(const PlanningProblem& problem, const PrmOptions& options) {
  IntegrationSettings settings;
  settings.delta_g = std::clamp(options.delta_g_fraction, kMinDeltaGFraction, kMaxDeltaGFraction) *
                     problem.map->geometry().cell;
  return settings;
}

}  // namespace

KinodynamicPrm::KinodynamicPrm(const PlanningProblem& problem, const PrmOptions& options)
    : problem_(&problem),
      options_(options),
      bound_(problem.limits.v_max, problem.limits.a_max),
      integrator_(problem, settingsFor(problem, options)),
      index_(problem.map->geometry().width(), problem.map->geometry().height(),
             options.bucket_size_m),
      rng_(options.seed),
      best_cost_(kInfinity) {
  options_.candidates = std::max<std::size_t>(1, options_.candidates);
  options_.gather_count = std::max(options_.gather_count, options_.candidates);
}

void KinodynamicPrm::clear() {
  roadmap_.clear();
  index_.clear();
  rng_.seed(options_.seed);
  best_cost_ = kInfinity;
  best_node_ = kNoParent;
  has_best_edge_ = false;
  alive_nodes_ = 0;
  pruned_nodes_ = 0;
  started_ = false;
  planned_ms_ = 0.0;
  progress_ = PlanResult{};
}

double KinodynamicPrm::plannedMs(const TerminationCondition& condition) const {
  return planned_ms_ + condition.elapsedSeconds() * 1e3;
}

double KinodynamicPrm::uniform() {
  // 53 random bits -> [0, 1): the same numbers on every platform (std:: distributions are
  // implementation-defined).
  constexpr double kScale = 1.0 / 9007199254740992.0;  // 2^-53
  return static_cast<double>(rng_() >> 11) * kScale;
}

bool KinodynamicPrm::blockedCell(const Eigen::Vector2d& position) const {
  const terrain::ElevationMap& map = *problem_->map;
  const std::optional<terrain::CellIndex> cell = map.geometry().cellAt(position);
  return !cell || map.isNoData(*cell) || map.isLethal(*cell);
}

bool KinodynamicPrm::sampleMilestone(Eigen::Vector2d& position, double& speed) {
  const GoalRegion& goal = problem_->goal;
  const terrain::GridGeometry& geometry = problem_->map->geometry();
  const double v_max = problem_->limits.v_max;
  const double pick = uniform();
  const double speed_pick = uniform();
  const double speed_value = uniform();
  speed = speed_pick < options_.full_speed_fraction ? v_max : speed_value * v_max;
  if (pick < options_.goal_bias) {
    // On the goal's approach axis: driving through it toward the goal ends aligned with the
    // goal heading.
    const double back = uniform() * options_.approach_axis_length_m;
    const double spread = goal.heading_tolerance >= kPi ? kPi : goal.heading_tolerance;
    const double angle = goal.heading + (2.0 * uniform() - 1.0) * kApproachAngleFraction * spread;
    position = goal.position - back * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    if (back <= goal.position_tolerance) speed = goal.v;
  } else if (best_node_ != kNoParent) {
    // Informed: only where L-(s0, m) + L-(m, sf) can beat the best cost; the ellipse with foci
    // start and goal and sum of distances v_max * L+ contains that set.
    const Eigen::Vector2d start = problem_->start.position;
    const double focal = (goal.position - start).norm();
    const double sum = v_max * best_cost_ + goal.position_tolerance;
    bool found = false;
    if (sum > focal) {
      const double a = 0.5 * sum;
      const double b = std::sqrt(std::max(0.0, a * a - 0.25 * focal * focal));
      const Eigen::Vector2d centre = 0.5 * (start + goal.position);
      const Eigen::Vector2d axis =
          focal > 0.0 ? Eigen::Vector2d((goal.position - start) / focal) : Eigen::Vector2d(1, 0);
      const Eigen::Vector2d normal(-axis.y(), axis.x());
      for (int i = 0; i < kInformedTries && !found; ++i) {
        const double x = (2.0 * uniform() - 1.0) * a;
        const double y = (2.0 * uniform() - 1.0) * b;
        const Eigen::Vector2d p = centre + x * axis + y * normal;
        if (geometry.contains(p) && (p - start).norm() + (p - goal.position).norm() <= sum) {
          position = p;
          found = true;
        }
      }
    }
    if (!found) position = {uniform() * geometry.width(), uniform() * geometry.height()};
  } else {
    position = {uniform() * geometry.width(), uniform() * geometry.height()};
  }
  return !blockedCell(position);
}

std::int32_t KinodynamicPrm::addNode(const PrmNode& node) {
  const std::int32_t id = roadmap_.add(node);
  index_.insert(id, node.state.position);
  ++alive_nodes_;
  return id;
}

void KinodynamicPrm::pruneNodes() {
  // Nodes that cannot lead to a better solution (001_... IV.A) leave the index; they stay in
  // the roadmap as ancestors of the nodes still alive.
  for (std::size_t i = 1; i < roadmap_.size(); ++i) {
    PrmNode& node = roadmap_.node(static_cast<std::int32_t>(i));
    if (!node.alive) continue;
    if (node.cost + bound_.toGoal(node.state, problem_->goal) >= best_cost_) {
      node.alive = false;
      index_.remove(static_cast<std::int32_t>(i), node.state.position);
      --alive_nodes_;
      ++pruned_nodes_;
    }
  }
}

void KinodynamicPrm::recordSolution(std::int32_t id, const ExtensionRequest* edge, double cost,
                                    double elapsed_ms, PlanResult& result) {
  best_cost_ = cost;
  best_node_ = id;
  has_best_edge_ = edge != nullptr;
  if (edge != nullptr) best_edge_ = *edge;
  if (!result.first_solution_ms) {
    result.first_solution_ms = elapsed_ms;
    result.first_solution_cost_s = cost;
  }
  result.cost_history.push_back({elapsed_ms, cost});
  ++result.statistics.improvements;
  pruneNodes();
}

void KinodynamicPrm::tryGoalConnection(std::int32_t id, double elapsed_ms, PlanResult& result) {
  const PrmNode node = roadmap_.node(id);
  const GoalRegion& goal = problem_->goal;
  if (node.cost + bound_.toGoal(node.state, goal) >= best_cost_) return;
  ++result.statistics.goal_attempts;
  ExtensionRequest request;
  request.target = goal.position;
  request.target_speed = goal.v;
  request.turn_speed = goal.v;
  request.max_length = kGoalConnectionLengthFactor * options_.goal_connection_radius_m;
  const ExtensionStatus status = integrator_.extend(node.state, request, goal_extension_);
  if (extensionSucceeded(status) && goal.contains(goal_extension_.end)) {
    ++result.statistics.goal_connections;
    const double cost = node.cost + goal_extension_.duration;
    if (cost < best_cost_) recordSolution(id, &request, cost, elapsed_ms, result);
    return;
  }
  // Steering straight at the goal arrives along the line from the end of the turn, which may
  // miss the goal heading: go through a point on the goal's approach axis first (a new node),
  // then to the goal.
  if (goal.heading_tolerance >= kPi) return;
  const models::VehicleLimits& limits = problem_->limits;
  for (int attempt = 0; attempt < kApproachTries; ++attempt) {
    // A random point behind the goal, within the heading tolerance of its axis.
    const double back =
        kApproachDistanceMin + uniform() * (kApproachDistanceMax - kApproachDistanceMin);
    const double angle =
        goal.heading + (2.0 * uniform() - 1.0) * kApproachAngleFraction * goal.heading_tolerance;
    const Eigen::Vector2d via =
        goal.position - back * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    if ((via - node.state.position).norm() <= back || blockedCell(via)) continue;
    ExtensionRequest to_via;
    to_via.target = via;
    // The fastest speed from which the goal speed can still be reached over `back`.
    to_via.target_speed =
        std::min(limits.v_max, std::sqrt(goal.v * goal.v + 2.0 * limits.a_max * back));
    to_via.turn_speed = to_via.target_speed;
    to_via.max_length = request.max_length;
    if (!extensionSucceeded(integrator_.extend(node.state, to_via, extension_))) continue;
    const PlannerState at_via = extension_.end;
    const double via_cost = node.cost + extension_.duration;
    if (via_cost + bound_.toGoal(at_via, goal) >= best_cost_) continue;
    if (!extensionSucceeded(integrator_.extend(at_via, request, goal_extension_)) ||
        !goal.contains(goal_extension_.end)) {
      continue;
    }
    ++result.statistics.goal_connections;
    const double cost = via_cost + goal_extension_.duration;
    if (cost >= best_cost_) continue;
    PrmNode child;
    child.state = at_via;
    child.cost = via_cost;
    child.parent = id;
    child.edge = to_via;
    const std::int32_t via_id = addNode(child);
    recordSolution(via_id, &request, cost, elapsed_ms, result);
    return;
  }
}

PlanResult KinodynamicPrm::solve(TerminationCondition condition) {
  condition.start();
  // What earlier calls found and counted carries on (clear() forgets it).
  PlanResult result;
  result.first_solution_ms = progress_.first_solution_ms;
  result.first_solution_cost_s = progress_.first_solution_cost_s;
  result.statistics = progress_.statistics;
  result.cost_history = progress_.cost_history;
  const auto elapsed_ms = [&] { return plannedMs(condition); };

  std::string stop_reason;
  if (condition.timeLimitSeconds() <= 0.0) {
    stop_reason = "the time limit is 0 s: no search was run";
  } else if (condition.iterationLimit() == 0) {
    stop_reason = "the iteration limit is 0: no search was run";
  } else {
    const bool fresh = !started_;
    if (fresh) {
      roadmap_.reserve(options_.reserve_nodes);
      PrmNode root;
      root.state = problem_->start;
      addNode(root);
      started_ = true;
    }
    const PlannerState start = roadmap_.node(0).state;
    if (problem_->goal.contains(start)) {
      // Nothing to drive (every planner): the one-row trajectory, at once.
      planStartInGoal(*problem_, result);
      result.nodes = roadmap_.size();
      result.planning_time_ms = elapsed_ms();
      return result;
    }
    if (fresh &&
        (start.position - problem_->goal.position).norm() <= options_.goal_connection_radius_m) {
      tryGoalConnection(0, elapsed_ms(), result);
    }
    stop_reason = growRoadmap(condition, result);
  }

  result.statistics.pruned_nodes = pruned_nodes_;
  result.nodes = roadmap_.size();
  if (best_node_ != kNoParent) {
    // One solution, the best; applyPlanVerdict() judges it and fills the result's summary.
    result.status = PlanStatus::kSolved;
    PlanSolution solution;
    solution.trajectory =
        trajectoryTo(best_node_, has_best_edge_ ? &best_edge_ : nullptr, solution.length_m);
    solution.cost_s = solution.search_cost_s = best_cost_;
    solution.found_ms = result.cost_history.back().time_ms;
    result.solutions.push_back(std::move(solution));
  } else {
    result.status = PlanStatus::kNoSolution;
    result.reason = stop_reason;
  }
  progress_.first_solution_ms = result.first_solution_ms;
  progress_.first_solution_cost_s = result.first_solution_cost_s;
  progress_.statistics = result.statistics;
  progress_.cost_history = result.cost_history;
  applyPlanVerdict(*problem_, result);
  result.planning_time_ms = elapsed_ms();
  planned_ms_ = result.planning_time_ms;
  return result;
}

std::string KinodynamicPrm::growRoadmap(TerminationCondition& condition, PlanResult& result) {
  const GoalRegion& goal = problem_->goal;
  std::size_t iterations = 0;
  while (!condition.shouldStop(iterations, best_node_ != kNoParent)) {
    ++iterations;
    if (roadmap_.size() >= options_.max_nodes) {
      result.statistics.iterations += iterations;
      return "the roadmap reached its node cap";
    }
    Eigen::Vector2d milestone;
    double milestone_speed = 0.0;
    if (!sampleMilestone(milestone, milestone_speed)) continue;
    // A milestone through which no trajectory can beat the best one is not tried.
    const double milestone_to_goal =
        std::max(0.0, (goal.position - milestone).norm() - goal.position_tolerance) /
        problem_->limits.v_max;
    if (best_node_ != kNoParent &&
        bound_.toPoint(problem_->start, milestone, 0.0, problem_->limits.v_max) +
                milestone_to_goal >=
            best_cost_) {
      continue;
    }
    extendTowards(milestone, milestone_speed, milestone_to_goal, condition, result);
  }
  result.statistics.iterations += iterations;
  std::ostringstream text;
  if (condition.timeUp()) {
    text << "no trajectory reached the goal region within the time limit of "
         << condition.timeLimitSeconds() << " s";
  } else {
    text << "no trajectory reached the goal region within " << iterations << " iterations";
  }
  return text.str();
}

void KinodynamicPrm::extendTowards(const Eigen::Vector2d& milestone, double milestone_speed,
                                   double milestone_to_goal, TerminationCondition& condition,
                                   PlanResult& result) {
  const GoalRegion& goal = problem_->goal;
  const bool solved = best_node_ != kNoParent;
  const double end_tolerance =
      integrator_.settings().end_tolerance_fraction * integrator_.settings().delta_g;
  // Candidates near the milestone, in ascending order of the bang-bang bound L-(s, m) (or of
  // L(s0, s) + L-(s, m) once solved, in optimisation mode).
  index_.gather(milestone, options_.gather_count, gathered_);
  ranked_.clear();
  for (const std::int32_t id : gathered_) {
    const PrmNode& node = roadmap_.node(id);
    if ((milestone - node.state.position).norm() <= end_tolerance) continue;
    const double lower = bound_.toPoint(node.state, milestone, milestone_speed, milestone_speed);
    if (solved && node.cost + lower + milestone_to_goal >= best_cost_) continue;
    const double key =
        solved && options_.total_cost_order_after_solution ? node.cost + lower : lower;
    ranked_.emplace_back(key, id);
  }
  const std::size_t tries = std::min(options_.candidates, ranked_.size());
  std::partial_sort(ranked_.begin(), ranked_.begin() + static_cast<std::ptrdiff_t>(tries),
                    ranked_.end());
  for (std::size_t i = 0; i < tries; ++i) {
    if (condition.timeUp()) break;
    const std::int32_t parent = ranked_[i].second;
    const PrmNode from = roadmap_.node(parent);
    ExtensionRequest request;
    request.target = milestone;
    request.target_speed = milestone_speed;
    request.turn_speed = milestone_speed;
    request.max_length = options_.extension_length_m;
    ++result.statistics.attempts;
    const ExtensionStatus status = integrator_.extend(from.state, request, extension_);
    if (!extensionSucceeded(status) || extension_.length <= 0.0) {
      ++result.statistics.trapped;
      continue;
    }
    const double cost = from.cost + extension_.duration;
    // Branch and bound: L(s0, sr) + L-(sr, sf) < L+(s0, sf), else discarded as if infeasible.
    if (cost + bound_.toGoal(extension_.end, goal) >= best_cost_) {
      ++result.statistics.pruned;
      continue;
    }
    PrmNode child;
    child.state = extension_.end;
    child.cost = cost;
    child.parent = parent;
    child.edge = request;
    const std::int32_t id = addNode(child);
    const double elapsed_ms = plannedMs(condition);
    if (goal.contains(child.state)) {
      recordSolution(id, nullptr, cost, elapsed_ms, result);
    } else if ((child.state.position - goal.position).norm() <= options_.goal_connection_radius_m) {
      tryGoalConnection(id, elapsed_ms, result);
    }
    return;
  }
}

models::Trajectory KinodynamicPrm::trajectoryTo(std::int32_t id, const ExtensionRequest* final_edge,
                                                double& length_m) {
  models::Trajectory trajectory;
  trajectory.has_column.fill(true);
  length_m = 0.0;
  const std::vector<std::int32_t> path = roadmap_.pathTo(id);
  Extension edge;
  const auto append = [&](const PlannerState& from, const ExtensionRequest& request, double t0) {
    integrator_.extend(from, request, edge);
    for (std::size_t i = trajectory.samples.empty() ? 0 : 1; i < edge.points.size(); ++i) {
      trajectory.samples.push_back(trajectorySample(edge.points[i], t0));
    }
    length_m += edge.length;
  };
  for (std::size_t i = 1; i < path.size(); ++i) {
    const PrmNode& parent = roadmap_.node(path[i - 1]);
    append(parent.state, roadmap_.node(path[i]).edge, parent.cost);
  }
  const PrmNode& last = roadmap_.node(id);
  if (final_edge != nullptr) {
    append(last.state, *final_edge, last.cost);
  } else if (trajectory.samples.empty()) {
    // The start already lies in the goal region: one sample.
    ExtensionRequest stay;
    stay.target = last.state.position;
    stay.target_speed = last.state.v;
    append(last.state, stay, 0.0);
  }
  return trajectory;
}

}  // namespace terratraj::search
