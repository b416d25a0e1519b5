#include "terratraj/search/kinodynamic_prm.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "search_fixtures.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::search {
namespace {

using terrain::TerrainKind;
using testing::makeWorld;
using testing::TestWorld;

TEST(KinodynamicPrm, SolvesFlatGroundNearTheBound) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kFlat, 128);
  KinodynamicPrm planner(world->problem);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(0.3));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  ASSERT_TRUE(result.first_solution_ms.has_value());
  EXPECT_LE(*result.first_solution_ms, result.planning_time_ms);
  const BangBangBound bound(world->problem.limits.v_max, world->problem.limits.a_max);
  const double lower = bound.toGoal(world->problem.start, world->problem.goal);
  EXPECT_GE(result.best_cost_s, lower);
  EXPECT_LE(result.best_cost_s, 1.25 * lower);  // straight, flat: close to the bound
  EXPECT_DOUBLE_EQ(result.trajectory.samples.back().t, result.best_cost_s);
  const CheckReport report = TrajectoryChecker(world->problem).check(result.trajectory);
  EXPECT_TRUE(report.ok()) << report.summary();
  // Anytime: the history decreases and ends at the best cost.
  ASSERT_FALSE(result.cost_history.empty());
  for (std::size_t i = 1; i < result.cost_history.size(); ++i) {
    EXPECT_LT(result.cost_history[i].cost_s, result.cost_history[i - 1].cost_s);
    EXPECT_GE(result.cost_history[i].time_ms, result.cost_history[i - 1].time_ms);
  }
  EXPECT_DOUBLE_EQ(result.cost_history.back().cost_s, result.best_cost_s);
  EXPECT_GT(result.statistics.attempts, 0u);
  EXPECT_GE(result.trappedFraction(), 0.0);
  EXPECT_LE(result.trappedFraction(), 1.0);
}

// Every returned trajectory satisfies every limit and avoids every lethal cell, re-checked by
// the independent checker, on 20 seeds of small maps of four kinds.
TEST(KinodynamicPrm, EveryTrajectoryPassesTheIndependentChecker) {
  const TerrainKind kinds[] = {TerrainKind::kHills, TerrainKind::kObstacles, TerrainKind::kCorridor,
                               TerrainKind::kForest};
  int solved = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const TerrainKind kind = kinds[seed % 4];
    const std::unique_ptr<TestWorld> world = makeWorld(kind, 96, seed);
    world->problem.limits.sigma_max = 0.5;
    world->problem.limits.omega_max = 0.8;
    world->problem.goal.heading_tolerance = 0.5;
    ASSERT_FALSE(world->problem.validate().has_value()) << *world->problem.validate();
    PrmOptions options;
    options.seed = seed;
    KinodynamicPrm planner(world->problem, options);
    const PlanResult result =
        planner.solve(TerminationCondition::timeLimit(0.5).maxIterations(4000));
    if (result.status != PlanStatus::kSolved) continue;
    ++solved;
    const CheckReport report = TrajectoryChecker(world->problem).check(result.trajectory);
    EXPECT_TRUE(report.ok()) << terrain::terrainKindName(kind) << " seed " << seed << ":\n"
                             << report.summary();
  }
  EXPECT_GE(solved, 16);
}

TEST(KinodynamicPrm, DeterministicForASeed) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kHills, 96, 5);
  PrmOptions options;
  options.seed = 11;
  KinodynamicPrm planner(world->problem, options);
  const PlanResult a = planner.solve(TerminationCondition::iterationLimit(600));
  planner.clear();
  const PlanResult b = planner.solve(TerminationCondition::iterationLimit(600));
  ASSERT_EQ(a.status, PlanStatus::kSolved) << a.reason;
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.statistics.attempts, b.statistics.attempts);
  EXPECT_EQ(a.best_cost_s, b.best_cost_s);
  ASSERT_EQ(a.trajectory.samples.size(), b.trajectory.samples.size());
  for (std::size_t i = 0; i < a.trajectory.samples.size(); ++i) {
    EXPECT_EQ(a.trajectory.samples[i].x, b.trajectory.samples[i].x);
    EXPECT_EQ(a.trajectory.samples[i].v, b.trajectory.samples[i].v);
  }
  options.seed = 12;
  KinodynamicPrm other(world->problem, options);
  const PlanResult c = other.solve(TerminationCondition::iterationLimit(600));
  EXPECT_TRUE(c.nodes != a.nodes || c.best_cost_s != a.best_cost_s);
}

// solve() called again continues the roadmap (a replanning loop's use): two calls of 300
// iterations end exactly where one call of 600 does, and a further call never loses the best
// solution.
TEST(KinodynamicPrm, ContinuesItsRoadmapWhenCalledAgain) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kHills, 96, 5);
  PrmOptions options;
  options.seed = 11;
  KinodynamicPrm once(world->problem, options);
  const PlanResult whole = once.solve(TerminationCondition::iterationLimit(600));
  ASSERT_EQ(whole.status, PlanStatus::kSolved) << whole.reason;

  KinodynamicPrm twice(world->problem, options);
  const PlanResult first = twice.solve(TerminationCondition::iterationLimit(300));
  const PlanResult second = twice.solve(TerminationCondition::iterationLimit(300));
  ASSERT_EQ(second.status, PlanStatus::kSolved) << second.reason;
  EXPECT_GE(second.nodes, first.nodes);
  EXPECT_EQ(second.nodes, whole.nodes);
  EXPECT_EQ(second.statistics.iterations, whole.statistics.iterations);
  EXPECT_EQ(second.statistics.attempts, whole.statistics.attempts);
  EXPECT_EQ(second.best_cost_s, whole.best_cost_s);
  EXPECT_EQ(second.cost_history.size(), whole.cost_history.size());
  if (first.status == PlanStatus::kSolved) {
    EXPECT_LE(second.best_cost_s, first.best_cost_s);
  }

  const PlanResult third = twice.solve(TerminationCondition::iterationLimit(200));
  ASSERT_EQ(third.status, PlanStatus::kSolved) << third.reason;
  EXPECT_LE(third.best_cost_s, second.best_cost_s);
  EXPECT_GE(third.nodes, second.nodes);
  EXPECT_EQ(third.statistics.iterations, whole.statistics.iterations + 200);

  // clear() starts over: the same as a new planner.
  twice.clear();
  const PlanResult again = twice.solve(TerminationCondition::iterationLimit(600));
  EXPECT_EQ(again.nodes, whole.nodes);
  EXPECT_EQ(again.best_cost_s, whole.best_cost_s);
}

// The time limit holds within 5 % or 10 ms, with and without a reachable goal.
TEST(KinodynamicPrm, HonoursTheTimeLimit) {
  std::unique_ptr<TestWorld> open = makeWorld(TerrainKind::kHills, 96, 2);
  std::unique_ptr<TestWorld> closed = makeWorld(TerrainKind::kFlat, 96);
  // A lethal ring around the goal: no solution exists.
  terrain::GridLayer& lethal = closed->map.addLayer(terrain::layer_names::kLethal, 0.0f);
  const terrain::CellIndex goal_cell =
      *closed->map.geometry().cellAt(closed->problem.goal.position);
  for (int dr = -6; dr <= 6; ++dr) {
    for (int dc = -6; dc <= 6; ++dc) {
      if (std::max(std::abs(dr), std::abs(dc)) == 6)
        lethal(goal_cell.row + dr, goal_cell.col + dc) = 1;
    }
  }
  // The best of three runs is held to the slack: on this 2-core machine, with ctest running two
  // test binaries, a run was once descheduled 14 ms past it (124 ms for 100); an overrun of the
  // planner's own making shows in every run. Never under the limit, in any run.
  for (TestWorld* world : {open.get(), closed.get()}) {
    for (const double limit : {0.1, 0.4}) {
      double best_wall = std::numeric_limits<double>::infinity();
      double best_planned = std::numeric_limits<double>::infinity();
      for (int run = 0; run < 3; ++run) {
        KinodynamicPrm planner(world->problem);
        const auto t0 = std::chrono::steady_clock::now();
        const PlanResult result = planner.solve(TerminationCondition::timeLimit(limit));
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        EXPECT_GE(result.planning_time_ms / 1e3, limit) << "limit " << limit;
        best_wall = std::min(best_wall, wall);
        best_planned = std::min(best_planned, result.planning_time_ms / 1e3);
        if (world == closed.get()) {
          EXPECT_EQ(result.status, PlanStatus::kNoSolution);
          EXPECT_NE(result.reason.find("time limit"), std::string::npos) << result.reason;
          EXPECT_TRUE(result.trajectory.samples.empty());
        }
      }
      const double slack = std::max(0.05 * limit, 0.010);
      EXPECT_NEAR(best_wall, limit, slack) << "limit " << limit;
      EXPECT_NEAR(best_planned, limit, slack) << "limit " << limit;
    }
  }
}

TEST(KinodynamicPrm, ZeroTimeLimitIsAClearNoSolution) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kFlat, 64);
  KinodynamicPrm planner(world->problem);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(0.0));
  EXPECT_EQ(result.status, PlanStatus::kNoSolution);
  EXPECT_NE(result.reason.find("0 s"), std::string::npos);
  EXPECT_EQ(result.nodes, 0u);
  EXPECT_FALSE(result.first_solution_ms.has_value());
  EXPECT_EQ(result.trappedFraction(), 0.0);
  EXPECT_EQ(planner.solve(TerminationCondition::timeLimit(-1.0)).status, PlanStatus::kNoSolution);
}

TEST(KinodynamicPrm, GoalHeadingAndSpeedTolerancesHold) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kFlat, 96);
  world->problem.goal.heading = 1.2;  // arrive heading north-north-east
  world->problem.goal.heading_tolerance = 0.2;
  world->problem.goal.v = 0.4;
  world->problem.goal.speed_tolerance = 0.05;
  KinodynamicPrm planner(world->problem);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(0.5));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  const models::TrajectorySample& last = result.trajectory.samples.back();
  EXPECT_LE(std::abs(wrapAngle(last.heading - 1.2)), 0.2);
  EXPECT_LE(std::abs(last.v - 0.4), 0.05);
  EXPECT_TRUE(TrajectoryChecker(world->problem).check(result.trajectory).ok());
}

// Kinodynamic tables cap the speed wherever they apply (v_max by pitch, by roll x curvature).
TEST(KinodynamicPrm, TablesCapTheSpeed) {
  const std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kHills, 96, 4);
  const models::PitchSpeedTable pitch_table(models::BinEdges({-1.0, -0.05, 0.05, 1.0}, "pitch"),
                                            {0.5, 0.9, 0.4});
  Eigen::MatrixXd roll_caps(2, 2);
  roll_caps << 0.7, 0.3, 0.3, 0.7;  // turning toward the lower side is slow
  const models::RollCurvatureSpeedTable roll_table(models::BinEdges({-1.0, 0.0, 1.0}, "roll"),
                                                   models::BinEdges({-2.0, 0.0, 2.0}, "curvature"),
                                                   roll_caps);
  world->problem.pitch_table = &pitch_table;
  world->problem.roll_curvature_table = &roll_table;
  KinodynamicPrm planner(world->problem);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(0.3));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  double fastest = 0.0;
  for (const models::TrajectorySample& s : result.trajectory.samples) {
    EXPECT_LE(s.v, pitch_table.lookup(s.pitch) + 1e-9);
    EXPECT_LE(s.v, roll_table.lookup(s.roll, s.curvature) + 1e-9);
    fastest = std::max(fastest, s.v);
  }
  EXPECT_LE(fastest, 0.9 + 1e-9);
  const CheckReport report = TrajectoryChecker(world->problem).check(result.trajectory);
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST(PlanningProblem, ValidateNamesTheFieldAtFault) {
  std::unique_ptr<TestWorld> world = makeWorld(TerrainKind::kFlat, 64);
  PlanningProblem& p = world->problem;
  EXPECT_FALSE(p.validate().has_value());
  const PlannerState start = p.start;
  p.start.position = {-1.0, 3.0};
  EXPECT_NE(p.validate()->find("off the map"), std::string::npos);
  p.start = start;
  p.start.v = 2.0 * p.limits.v_max;
  EXPECT_NE(p.validate()->find("start.v"), std::string::npos);
  p.start = start;
  p.start.v = 1.0;
  p.start.curvature = 5.0;
  EXPECT_NE(p.validate()->find("start.curvature"), std::string::npos);
  p.start = start;
  terrain::GridLayer& lethal = world->map.addLayer(terrain::layer_names::kLethal, 0.0f);
  const terrain::CellIndex cell = *world->map.geometry().cellAt(p.goal.position);
  lethal(cell) = 1.0f;
  EXPECT_NE(p.validate()->find("goal"), std::string::npos);
  EXPECT_NE(p.validate()->find("lethal"), std::string::npos);
  lethal(cell) = 0.0f;
  world->map.elevation()(cell) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(p.validate()->find("no-data"), std::string::npos);
  world->map.elevation()(cell) = 0.0f;
  p.limits.a_max = 0.0;
  EXPECT_NE(p.validate()->find("limits.a_max"), std::string::npos);
  p.limits.a_max = 0.5;
  std::unique_ptr<TestWorld> ramp = makeWorld(TerrainKind::kRamp, 64);
  ramp->problem.limits.pitch_max = 0.01;
  ramp->problem.limits.roll_max = 0.01;
  EXPECT_NE(ramp->problem.validate()->find("exceeds"), std::string::npos);
}

TEST(SpatialGridIndex, GatherIncludesTheNearestNodes) {
  SpatialGridIndex index(100.0, 100.0, 4.0);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> coordinate(0.0, 100.0);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 20000; ++i) {
    points.emplace_back(coordinate(rng), coordinate(rng));
    index.insert(i, points.back());
  }
  for (int i = 0; i < 10000; i += 2) index.remove(i, points[static_cast<std::size_t>(i)]);
  EXPECT_EQ(index.size(), 15000u);
  std::vector<std::int32_t> out;
  for (int q = 0; q < 100; ++q) {
    const Eigen::Vector2d query(coordinate(rng), coordinate(rng));
    index.gather(query, 16, out);
    ASSERT_GE(out.size(), 16u);
    int nearest = -1;
    double best = 1e300;
    for (int i = 0; i < 20000; ++i) {
      if (i < 10000 && i % 2 == 0) continue;
      const double d = (points[static_cast<std::size_t>(i)] - query).norm();
      if (d < best) best = d, nearest = i;
    }
    EXPECT_NE(std::find(out.begin(), out.end(), nearest), out.end());
    for (const std::int32_t id : out) EXPECT_FALSE(id < 10000 && id % 2 == 0);
  }
}

}  // namespace
}  // namespace terratraj::search
