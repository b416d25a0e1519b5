#include "terratraj/bench/ompl_peer.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "ompl_adapters.hpp"
#include "terratraj/search/plan_verdict.hpp"

namespace terratraj::bench {

using namespace detail;  // the adapters of ompl_adapters.hpp

// Everything OMPL needs for one problem, built once; solve() calls continue its planner.
struct OmplPeerPlanner::Impl {
  Impl(const search::PlanningProblem& problem_in, OmplPlanner kind_in)
      : problem(problem_in), kind(kind_in) {
    build();
  }
  void build();
  void makePlanner();

  const search::PlanningProblem& problem;
  OmplPlanner kind;
  std::shared_ptr<oc::SpaceInformation> si;
  std::shared_ptr<ExtensionPropagator> propagator;
  std::shared_ptr<ob::ProblemDefinition> pdef;
  ob::PlannerPtr planner;
  SolutionRecorder recorder;
  double planned_ms = 0.0;
  std::string status = "not run";
  // The fastest re-integrated solution over the solve() calls since the last clear(): the
  // problem definition's path after a later call can re-integrate slower than an earlier one
  // (SST ranks its paths by its own cost; seen under ASan: 40.5 s after 40.145 s).
  std::optional<search::PlanSolution> best;
};

void OmplPeerPlanner::Impl::build() {
  const OmplPlanner planner_kind = kind;
  const terrain::GridGeometry& g = problem.map->geometry();
  auto se2 = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds xy(2);
  xy.setLow(0, 0.0);
  xy.setHigh(0, g.width());
  xy.setLow(1, 0.0);
  xy.setHigh(1, g.height());
  se2->setBounds(xy);
  // Heading counts as much as 3 m per rad in distances: a node at the goal position with the
  // wrong heading is not "near" a goal sample.
  se2->setSubspaceWeight(1, 3.0);
  auto vk = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds vk_bounds(2);
  vk_bounds.setLow(0, 0.0);
  vk_bounds.setHigh(0, problem.limits.v_max);
  vk_bounds.setLow(1, -problem.limits.kappa_max);
  vk_bounds.setHigh(1, problem.limits.kappa_max);
  vk->setBounds(vk_bounds);
  auto time = std::make_shared<ob::RealVectorStateSpace>(1);
  time->setBounds(0.0, kMaxTimeS);
  auto space = std::make_shared<ob::CompoundStateSpace>();
  space->addSubspace(se2, 1.0);
  space->addSubspace(vk, 0.5);
  space->addSubspace(time, 0.0);
  auto controls = std::make_shared<oc::RealVectorControlSpace>(space, kControlDims);
  ob::RealVectorBounds u(kControlDims);
  u.setLow(0, 0.0);
  u.setHigh(0, g.width());
  u.setLow(1, 0.0);
  u.setHigh(1, g.height());
  u.setLow(2, 0.0);
  u.setHigh(2, problem.limits.v_max);
  u.setLow(3, -M_PI);
  u.setHigh(3, M_PI);
  u.setLow(4, 0.0);
  u.setHigh(4, kMaxApproachM);
  controls->setBounds(u);
  if (planner_kind == OmplPlanner::kSst) {
    const search::GoalRegion goal = problem.goal;
    controls->setControlSamplerAllocator(
        [goal](const oc::ControlSpace* control_space) -> oc::ControlSamplerPtr {
          return std::make_shared<GoalBiasedControlSampler>(control_space, goal);
        });
  }

  si = std::make_shared<oc::SpaceInformation>(space, controls);
  propagator = std::make_shared<ExtensionPropagator>(si, problem);
  si->setStatePropagator(propagator);
  si->setStateValidityChecker(std::make_shared<TerrainValidityChecker>(si, problem));
  si->setPropagationStepSize(kStepS);
  si->setMinMaxControlDuration(1, kMaxSteps);
  if (planner_kind == OmplPlanner::kRrt) {
    const ExtensionPropagator* p = propagator.get();
    const double jitter = 0.8 * problem.goal.heading_tolerance;
    si->setDirectedControlSamplerAllocator(
        [p, jitter](const oc::SpaceInformation* s) -> oc::DirectedControlSamplerPtr {
          return std::make_shared<SteeringControlSampler>(s, *p, jitter);
        });
  }
  si->setup();

  makePlanner();
}

// A new problem definition (start, goal, objective) and planner: no tree, no solution.
void OmplPeerPlanner::Impl::makePlanner() {
  pdef = std::make_shared<ob::ProblemDefinition>(si);
  const ob::StateSpacePtr& space = si->getStateSpace();
  ob::ScopedState<> start(space);
  setState(start.get(), problem.start, 0.0);
  pdef->addStartState(start);
  recorder = SolutionRecorder{};
  pdef->setGoal(std::make_shared<GoalRegionAdapter>(si, problem.goal, recorder));
  pdef->setOptimizationObjective(std::make_shared<TimeObjective>(si));

  if (kind == OmplPlanner::kRrt) {
    auto rrt = std::make_shared<oc::RRT>(si);
    rrt->setGoalBias(0.05);
    planner = rrt;
  } else {
    auto sst = std::make_shared<oc::SST>(si);
    sst->setSelectionRadius(1.0);  // [m-scale state distance]
    sst->setPruningRadius(0.5);
    planner = sst;
  }
  planner->setProblemDefinition(pdef);
  planner->setup();
}

bool omplPeersAvailable() { return true; }

OmplPeerPlanner::OmplPeerPlanner(const search::PlanningProblem& problem, OmplPlanner planner,
                                 std::uint64_t seed) {
  static const bool seeded = [seed] {
    ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
    ompl::RNG::setSeed(seed);
    return true;
  }();
  (void)seeded;
  impl_ = std::make_unique<Impl>(problem, planner);
}

OmplPeerPlanner::~OmplPeerPlanner() = default;

const char* OmplPeerPlanner::name() const { return omplPlannerName(impl_->kind); }

const std::string& OmplPeerPlanner::omplStatus() const { return impl_->status; }

void OmplPeerPlanner::clear() {
  impl_->makePlanner();
  impl_->planned_ms = 0.0;
  impl_->best.reset();
  impl_->status = "not run";
}

search::PlanResult OmplPeerPlanner::solve(search::TerminationCondition termination) {
  Impl& m = *impl_;
  termination.start();
  m.recorder.started = std::chrono::steady_clock::now();
  m.recorder.offset_ms = m.planned_ms;
  ob::PlannerTerminationCondition condition(
      [&termination] { return termination.timeUp() || termination.stopRequested(); });
  const ob::PlannerStatus status =
      termination.stopsAtFirstSolution()
          ? m.planner->solve(ob::plannerOrTerminationCondition(
                condition, ob::exactSolnPlannerTerminationCondition(m.pdef)))
          : m.planner->solve(condition);
  m.planned_ms += termination.elapsedSeconds() * 1e3;
  m.status = status.asString();

  search::PlanResult result;
  result.planning_time_ms = m.planned_ms;
  result.cost_history = m.recorder.improvements;
  if (!result.cost_history.empty()) {
    result.first_solution_ms = result.cost_history.front().time_ms;
    result.first_solution_cost_s = result.cost_history.front().cost_s;
  }
  if (m.pdef->hasExactSolution()) {
    auto* path = m.pdef->getSolutionPath()->as<oc::PathControl>();
    search::PlanSolution solution;
    solution.trajectory = reintegrate(*m.propagator, m.problem, *path);
    if (!solution.trajectory.samples.empty()) {
      solution.cost_s = solution.trajectory.samples.back().t;
    }
    solution.search_cost_s =
        result.cost_history.empty() ? solution.cost_s : result.cost_history.back().cost_s;
    solution.length_m = solution.trajectory.planarLength();
    solution.found_ms =
        result.cost_history.empty() ? m.planned_ms : result.cost_history.back().time_ms;
    // A solution never gets worse when solve() is called again (the planners' interface).
    if (!m.best || m.best->trajectory.samples.empty() ||
        (!solution.trajectory.samples.empty() && solution.cost_s < m.best->cost_s)) {
      m.best = solution;
    }
    result.solutions.push_back(*m.best);
    result.status = search::PlanStatus::kSolved;
  } else {
    result.reason = "OMPL: " + m.status;
  }
  search::applyPlanVerdict(m.problem, result);
  return result;
}

}  // namespace terratraj::bench
