// The OMPL peers of the planners suite: same problem, same propagator, same checks.

#include "terratraj/bench/ompl_peer.hpp"

#include <gtest/gtest.h>

#include "terratraj/bench/benchmark_world.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::bench {
namespace {

// On open hills both peers reach the goal region through the planners' interface: one
// solution that passed the verdict, starting at the start, ending in the goal region and
// passing the independent check.
TEST(OmplPeer, BothPeersSolveAnOpenProblemWithinTheLimits) {
  bench::BenchmarkWorld w(bench::generateBenchmarkMap(terrain::TerrainKind::kHills, 96, 1),
                          bench::BenchmarkVehicle::kPoint, bench::benchmarkLimits(25.0));
  ASSERT_TRUE(w.place({4.0, 12.0}, {18.0, 12.0}));
  for (const OmplPlanner kind : {OmplPlanner::kRrt, OmplPlanner::kSst}) {
    SCOPED_TRACE(omplPlannerName(kind));
    OmplPeerPlanner peer(w.problem, kind, 1);
    search::Planner& planner = peer;
    EXPECT_STREQ(planner.name(), omplPlannerName(kind));
    const search::PlanResult run = planner.solve(search::TerminationCondition::timeLimit(2.0));
    ASSERT_EQ(run.status, search::PlanStatus::kSolved) << run.reason << " / " << peer.omplStatus();
    ASSERT_EQ(run.solutions.size(), 1u);
    ASSERT_TRUE(run.first_solution_ms.has_value());
    EXPECT_LE(*run.first_solution_ms, run.planning_time_ms + 1e-9);
    ASSERT_GE(run.trajectory.samples.size(), 2u);
    const models::TrajectorySample& first = run.trajectory.samples.front();
    const models::TrajectorySample& last = run.trajectory.samples.back();
    EXPECT_NEAR(first.x, w.problem.start.position.x(), 1e-9);
    EXPECT_NEAR(first.y, w.problem.start.position.y(), 1e-9);
    search::PlannerState end;
    end.position = {last.x, last.y};
    end.heading = last.heading;
    end.v = last.v;
    EXPECT_LE(w.problem.goal.positionError(end), w.problem.goal.position_tolerance + 0.05);
    EXPECT_GT(run.best_cost_s, w.lowerBoundTime());
    EXPECT_DOUBLE_EQ(run.best_cost_s, last.t);
    search::CheckTolerances tolerances;
    tolerances.relative = 1e-3;
    const search::CheckReport check =
        search::TrajectoryChecker(w.problem, tolerances).check(run.trajectory);
    EXPECT_TRUE(check.ok()) << (check.violations.empty() ? "" : check.violations[0].limit);
  }
}

// SST called again continues its tree (the planners' interface): the best cost never gets
// worse and the times go on from the first call's; clear() forgets the solution.
TEST(OmplPeer, SstContinuesWhenCalledAgain) {
  bench::BenchmarkWorld w(bench::generateBenchmarkMap(terrain::TerrainKind::kHills, 96, 1),
                          bench::BenchmarkVehicle::kPoint, bench::benchmarkLimits(25.0));
  ASSERT_TRUE(w.place({4.0, 12.0}, {18.0, 12.0}));
  OmplPeerPlanner planner(w.problem, OmplPlanner::kSst, 1);
  const search::PlanResult first = planner.solve(search::TerminationCondition::timeLimit(1.0));
  ASSERT_EQ(first.status, search::PlanStatus::kSolved) << first.reason;
  const search::PlanResult second = planner.solve(search::TerminationCondition::timeLimit(0.3));
  ASSERT_EQ(second.status, search::PlanStatus::kSolved) << second.reason;
  EXPECT_LE(second.best_cost_s, first.best_cost_s + 1e-9);
  EXPECT_GT(second.planning_time_ms, first.planning_time_ms);
  EXPECT_EQ(second.first_solution_ms, first.first_solution_ms);
  planner.clear();
  const search::PlanResult none = planner.solve(search::TerminationCondition::timeLimit(0.0));
  EXPECT_EQ(none.status, search::PlanStatus::kNoSolution);
  EXPECT_TRUE(none.cost_history.empty());
}

}  // namespace
}  // namespace terratraj::bench
