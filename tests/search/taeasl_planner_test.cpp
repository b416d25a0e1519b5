#include "terratraj/search/taeasl_planner.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <set>

#include "lattice_fixtures.hpp"
#include "lattice_reference_search.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::search {
namespace {

using testing::block;
using testing::defaultPrimitives;
using testing::flatMap;
using testing::worldOn;

// Lowest / highest y of a trajectory's samples with x in [x0, x1].
std::pair<double, double> yRange(const models::Trajectory& t, double x0, double x1) {
  double lo = 1e9, hi = -1e9;
  for (const models::TrajectorySample& s : t.samples) {
    if (s.x >= x0 && s.x <= x1) lo = std::min(lo, s.y), hi = std::max(hi, s.y);
  }
  return {lo, hi};
}

// One block east of the map centre: its frame runs from the block's east side along y = 6 to
// the east edge. The route north of the block never crosses it; the route south must, to reach
// the goal at y = 8.
TEST(TaeaslPlanner, RoutesOnEitherSideOfABlockGetDifferentSignatures) {
  terrain::ElevationMap map = flatMap(48, 80);
  block(map, 11.0, 4.5, 13.0, 7.5);
  auto world = worldOn(std::move(map), {2.0, 6.0}, {18.0, 8.0});
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslOptions options;
  options.homotopy_classes = 2;
  TaeaslPlanner planner(graph, options);
  ASSERT_EQ(planner.frames().size(), 1u);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(60));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  ASSERT_EQ(result.solutions.size(), 2u);
  const TrajectoryChecker checker(world->problem);
  for (const PlanSolution& s : result.solutions) {
    EXPECT_TRUE(checker.check(s.trajectory).ok()) << s.homotopy;
    EXPECT_TRUE(s.proven_optimal);
    const auto [lo, hi] = yRange(s.trajectory, 11.0, 13.0);
    if (s.homotopy.empty()) {
      EXPECT_GT(lo, 7.5);  // north of the block
    } else {
      EXPECT_EQ(s.homotopy, "a+");
      EXPECT_LT(hi, 4.5);  // south of the block
    }
  }
  EXPECT_NE(result.solutions[0].homotopy, result.solutions[1].homotopy);
}

// The block's frame runs along y = 6 (the start's lattice row) east to the map edge; the goal
// lies 0.25 m south of it, so its region holds lattice states on the frame and south of it. A
// route is named by its path closed at the exact goal: north of the block "a-" (it must cross
// the frame to reach the goal), south "", wherever in the region each stops. Named by where
// they stop instead, a north route stopping on the frame and a south one stopping south of it
// would both be "".
TEST(TaeaslPlanner, RoutesAreNamedByTheirPathsClosedAtTheExactGoal) {
  terrain::ElevationMap map = flatMap(48, 80);
  block(map, 11.0, 4.5, 13.0, 7.5);
  auto world = worldOn(std::move(map), {2.0, 6.0}, {17.0, 5.75});
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslOptions options;
  options.homotopy_classes = 2;
  TaeaslPlanner planner(graph, options);
  ASSERT_EQ(planner.frames().size(), 1u);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(60));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  ASSERT_EQ(result.solutions.size(), 2u);
  std::set<std::string> names;
  for (const PlanSolution& s : result.solutions) {
    std::vector<Eigen::Vector2d> path;
    for (const models::TrajectorySample& p : s.trajectory.samples) path.emplace_back(p.x, p.y);
    EXPECT_EQ(
        planner.frames()
            .signatureBetween(world->problem.start.position, path, world->problem.goal.position)
            .toString(),
        s.homotopy);
    const auto [lo, hi] = yRange(s.trajectory, 11.0, 13.0);
    EXPECT_TRUE(lo > 7.5 || hi < 4.5) << "through the block? " << lo << " " << hi;
    EXPECT_EQ(s.homotopy, lo > 7.5 ? "a-" : "");
    names.insert(s.homotopy);
  }
  EXPECT_EQ(names.size(), 2u);
}

// Run to the end on a small map with two blocks, every class's solution costs what a brute-force
// Dijkstra over (lattice state, signature) finds for that class, and the classes returned are
// the cheapest ones.
TEST(TaeaslPlanner, EachSolutionIsTheCheapestOfItsClass) {
  terrain::ElevationMap map = flatMap(48, 80);
  block(map, 7.0, 4.0, 8.0, 7.0);
  block(map, 12.0, 6.0, 13.0, 9.0);
  auto world = worldOn(std::move(map), {2.0, 6.0}, {18.0, 6.5});
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslOptions options;
  options.homotopy_classes = 3;
  options.anchor = FrameAnchor::kStart;
  options.frame_radius = 20.0;
  options.max_signature_length = 3;
  TaeaslPlanner planner(graph, options);
  ASSERT_EQ(planner.frames().size(), 2u);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(120));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  ASSERT_EQ(result.solutions.size(), 3u);
  const std::map<std::string, double> reference =
      testing::referenceCosts(graph, &planner.frames(), 3, 3);
  ASSERT_EQ(reference.size(), 3u);
  const TrajectoryChecker checker(world->problem);
  std::set<std::string> names;
  for (const PlanSolution& s : result.solutions) {
    ASSERT_TRUE(reference.count(s.homotopy)) << "class " << s.homotopy << " is not a cheapest";
    EXPECT_NEAR(s.search_cost_s, reference.at(s.homotopy), 1e-9 * s.search_cost_s) << s.homotopy;
    EXPECT_TRUE(s.proven_optimal);
    EXPECT_TRUE(checker.check(s.trajectory).ok()) << s.homotopy;
    names.insert(s.homotopy);
  }
  EXPECT_EQ(names.size(), 3u);
}

TEST(TaeaslPlanner, NoLethalCellsMeansOneClass) {
  auto world = testing::makeWorld(terrain::TerrainKind::kHills, 128);
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslPlanner planner(graph);
  EXPECT_TRUE(planner.frames().empty());
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(30));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  ASSERT_EQ(result.solutions.size(), 1u);
  EXPECT_EQ(result.solutions[0].homotopy, "");
  EXPECT_TRUE(result.solutions[0].proven_optimal);
  EXPECT_EQ(result.search.homotopy_classes, 1u);
}

// 002_... III: a forest (many small clusters). A fixed expansion budget (about what 1 s buys on
// this machine; the time-limited figure is in docs/benchmarks.md) gives several classes, each
// collision-free under the independent check.
TEST(TaeaslPlanner, ForestGivesSeveralCheckedClasses) {
  auto world = testing::makeWorld(terrain::TerrainKind::kForest, 256);
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslPlanner planner(graph);
  EXPECT_GT(planner.frames().size(), 3u);
  const PlanResult result = planner.solve(TerminationCondition::iterationLimit(150000));
  ASSERT_EQ(result.status, PlanStatus::kSolved) << result.reason;
  EXPECT_GE(result.solutions.size(), 2u);
  std::set<std::string> names;
  const TrajectoryChecker checker(world->problem);
  for (const PlanSolution& s : result.solutions) {
    const CheckReport check = checker.check(s.trajectory);
    EXPECT_TRUE(check.ok()) << s.homotopy << ": " << check.summary();
    names.insert(s.homotopy);
  }
  EXPECT_EQ(names.size(), result.solutions.size());
}

// A search that cannot finish in the limit (a thousand classes wanted on a forest) stops on time:
// the search takes 85 % of the limit once a class is found, the rest builds the trajectory of
// every class found (tens of them); the slack allows for a loaded two-core machine.
TEST(TaeaslPlanner, TimeLimitIsHonoured) {
  auto world = testing::makeWorld(terrain::TerrainKind::kForest, 256);
  const LatticeGraph graph(world->problem, defaultPrimitives());
  TaeaslOptions options;
  options.homotopy_classes = 1000;
  const double limit_s = 0.3;
  double best_ms = std::numeric_limits<double>::infinity();
  for (int run = 0; run < 3; ++run) {  // best of three: scheduler noise is not the planner's
    TaeaslPlanner planner(graph, options);
    const PlanResult result = planner.solve(TerminationCondition::timeLimit(limit_s));
    EXPECT_GE(result.planning_time_ms, 0.8 * limit_s * 1e3);
    best_ms = std::min(best_ms, result.planning_time_ms);
  }
  EXPECT_LE(best_ms, 1.2 * limit_s * 1e3 + 20.0);
}

}  // namespace
}  // namespace terratraj::search
