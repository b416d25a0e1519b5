// The OMPL peers of the planners suite: same problem, same propagator, same checks.

#include "terratraj/bench/ompl_peer.hpp"

#include <gtest/gtest.h>

#include "terratraj/search/benchmark_world.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::bench {
namespace {

// On open hills both peers reach the goal region; the re-integrated trajectory starts at the
// start, ends in the goal region and passes the independent check.
TEST(OmplPeer, BothPeersSolveAnOpenProblemWithinTheLimits) {
  search::BenchmarkWorld w(search::generateBenchmarkMap(terrain::TerrainKind::kHills, 96, 1),
                           search::BenchmarkVehicle::kPoint, search::benchmarkLimits(25.0));
  ASSERT_TRUE(w.place({4.0, 12.0}, {18.0, 12.0}));
  for (const OmplPlanner planner : {OmplPlanner::kRrt, OmplPlanner::kSst}) {
    SCOPED_TRACE(omplPlannerName(planner));
    const OmplRun run = runOmplPeer(w.problem, planner, 2.0, 1);
    ASSERT_TRUE(run.solved) << run.status;
    ASSERT_TRUE(run.first_ms.has_value());
    EXPECT_LE(*run.first_ms, run.planning_ms + 1e-9);
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
    EXPECT_GT(run.cost_s, w.lowerBoundTime());
    search::CheckTolerances tolerances;
    tolerances.relative = 1e-3;
    const search::CheckReport check =
        search::TrajectoryChecker(w.problem, tolerances).check(run.trajectory);
    EXPECT_TRUE(check.ok()) << (check.violations.empty() ? "" : check.violations[0].limit);
  }
}

}  // namespace
}  // namespace terratraj::bench
