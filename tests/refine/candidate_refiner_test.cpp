// CandidateRefiner: candidates from the planners and hand-made paths refined into locally
// optimal trajectories, checked independently (re-simulation, TrajectoryChecker, signature).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "../search/lattice_fixtures.hpp"
#include "../search/search_fixtures.hpp"
#include "../terrain/test_maps.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace terratraj::search {
namespace {

using refine::CandidateRefiner;
using refine::RefinementOptions;
using refine::RefinementResult;
using refine::RefineMethod;

using ::testing::HasSubstr;
using testing::TestWorld;

// The boundary-value form of a world's problem (exact start and goal, minimum time).
ocp::BoundaryValueProblem bvpOf(const PlanningProblem& p) {
  ocp::BoundaryValueProblem bvp;
  bvp.start = {p.start.position.x(), p.start.position.y(), p.start.heading, p.start.v, 0.0};
  bvp.goal = {p.goal.position.x(), p.goal.position.y(), p.goal.heading, p.goal.v, 0.0};
  bvp.limits = p.limits;
  return bvp;
}

ReferenceFrames framesOf(const TestWorld& world) {
  ReferenceFrameOptions options;
  options.anchor = {0.5 * world.map.geometry().width(), 0.5 * world.map.geometry().height()};
  options.frame_radius = 100.0;
  return ReferenceFrames::build(world.map, terrain::findObstacleClusters(world.map), options);
}

// An x,y-only path through the given waypoints.
models::Trajectory xyPath(const std::vector<Eigen::Vector2d>& points) {
  models::Trajectory path;
  path.has_column[static_cast<std::size_t>(models::TrajectoryColumn::kX)] = true;
  path.has_column[static_cast<std::size_t>(models::TrajectoryColumn::kY)] = true;
  for (const Eigen::Vector2d& p : points) {
    models::TrajectorySample s = models::TrajectorySample::unknown();
    s.x = p.x();
    s.y = p.y();
    path.samples.push_back(s);
  }
  return path;
}

// Everything a converged refinement must satisfy, checked here without the refiner's word:
// the trajectory starts at the start and ends at the goal, the independent checker finds no
// violation, and its signature is the candidate's (both closed at the exact start and goal: the
// candidate may stop anywhere in the goal region).
void expectSound(const RefinementResult& r, const PlanningProblem& problem,
                 const ReferenceFrames& frames) {
  ASSERT_EQ(r.status, ocp::SolveStatus::kConverged) << r.reason;
  const models::Trajectory& t = r.verified.trajectory;
  ASSERT_GE(t.samples.size(), 2u);
  EXPECT_NEAR(t.samples.front().x, problem.start.position.x(), 1e-6);
  EXPECT_NEAR(t.samples.front().y, problem.start.position.y(), 1e-6);
  EXPECT_NEAR(t.samples.back().x, problem.goal.position.x(), 1e-3);
  EXPECT_NEAR(t.samples.back().y, problem.goal.position.y(), 1e-3);
  CheckTolerances tolerances;
  tolerances.relative = 1e-3;
  const CheckReport check = TrajectoryChecker(problem, tolerances).check(t);
  EXPECT_TRUE(check.ok()) << check.summary();
  std::vector<Eigen::Vector2d> xy;
  for (const models::TrajectorySample& s : t.samples) xy.emplace_back(s.x, s.y);
  std::vector<Eigen::Vector2d> candidate_xy;
  for (const models::TrajectorySample& s : r.candidate.samples) candidate_xy.emplace_back(s.x, s.y);
  const Eigen::Vector2d& start = problem.start.position;
  const Eigen::Vector2d& goal = problem.goal.position;
  EXPECT_EQ(frames.signatureBetween(start, xy, goal),
            frames.signatureBetween(start, candidate_xy, goal));
  EXPECT_TRUE(r.homotopy_kept);
}

// The PRM's first solution (anytime, not yet improved) on hills: the refinement is faster,
// although it drives to the goal itself where the candidate stopped in the goal region.
TEST(CandidateRefiner, PrmCandidateOnHillsBecomesFasterAndSound) {
  auto world = testing::makeWorld(terrain::TerrainKind::kHills, 96, 2);
  PrmOptions prm;
  prm.seed = 3;
  KinodynamicPrm planner(world->problem, prm);
  const PlanResult plan = planner.solve(TerminationCondition::timeLimit(1.0).stopAtFirstSolution());
  ASSERT_EQ(plan.status, PlanStatus::kSolved) << plan.reason;
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r = refiner.refine(plan.trajectory);
  expectSound(r, world->problem, frames);
  EXPECT_EQ(r.method, RefineMethod::kCollocation) << r.method_rule;  // 19 m: too long
  ASSERT_TRUE(r.candidate_figures && r.refined_figures);
  EXPECT_NEAR(r.candidate_figures->duration_s, plan.best_cost_s, 1e-9);
  EXPECT_LT(r.refined_figures->duration_s, r.candidate_figures->duration_s);
  // The bang-bang bound along the straight line is a lower bound of every trajectory.
  const double d = (world->problem.goal.position - world->problem.start.position).norm();
  const models::VehicleLimits& l = world->problem.limits;
  EXPECT_GT(r.refined_figures->duration_s, d / l.v_max + l.v_max / l.a_max - 1e-6);
  // The report's figures are the re-simulation's.
  EXPECT_NEAR(r.refined_figures->duration_s, r.verified.final_time, 1e-9);
  EXPECT_FALSE(r.history.empty());
}

TEST(CandidateRefiner, KeepsEachSideOfABlock) {
  terrain::ElevationMap map = testing::flatMap(64, 96);  // 24 m x 16 m
  testing::block(map, 10.0, 9.0, 14.0, 12.0);  // north of the anchor (12, 8): a frame north
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  ASSERT_EQ(frames.size(), 1u);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  std::vector<std::string> classes;
  for (const double side : {13.8, 6.0}) {  // north of the block, south of it
    SCOPED_TRACE(side);
    const RefinementResult r =
        refiner.refine(xyPath({{3.0, 8.0}, {8.0, side}, {16.0, side}, {21.0, 8.0}}));
    expectSound(r, world->problem, frames);
    classes.push_back(r.refined_figures->homotopy);
    // It stays on its side where it passes the block, at least the clearance away.
    for (const models::TrajectorySample& s : r.verified.trajectory.samples) {
      if (s.x > 10.0 && s.x < 14.0) {
        EXPECT_TRUE(side > 8.0 ? s.y > 12.0 + 0.2 : s.y < 9.0 - 0.2) << s.x << ", " << s.y;
      }
    }
    // Shorter than the candidate's detour, and with every column derived.
    EXPECT_LT(r.refined_figures->length_m, r.candidate_figures->length_m);
    EXPECT_THAT(r.derived_columns, ::testing::Contains("t"));
    EXPECT_THAT(r.derived_columns, ::testing::Contains("pitch"));
  }
  EXPECT_NE(classes[0], classes[1]);
}

// A block on the straight line, its frame running east along y = 8 past the goal (21, 7.8) to
// the map edge. The candidate passes north of the block and stops in the goal region north of
// the frame (as a lattice candidate can); the refinement drives to the exact goal, south of the
// frame. Compared as paths closed at the exact goal both are the north route ("a-"): the class
// is kept. (Compared as they stop, the candidate would be "" and the refinement "a-".)
TEST(CandidateRefiner, ACandidateStoppingAcrossAFrameFromTheGoalKeepsItsClass) {
  terrain::ElevationMap map = testing::flatMap(64, 96);  // 24 m x 16 m, anchor (12, 8)
  testing::block(map, 14.0, 7.0, 16.0, 9.0);
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 7.8});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  ASSERT_EQ(frames.size(), 1u);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const std::vector<Eigen::Vector2d> path{{3.0, 8.0}, {8.0, 10.5}, {17.0, 10.5}, {20.8, 8.2}};
  ASSERT_EQ(frames.signatureOf(path).toString(), "");
  const RefinementResult r = refiner.refine(xyPath(path));
  expectSound(r, world->problem, frames);
  ASSERT_TRUE(r.candidate_figures && r.refined_figures);
  EXPECT_EQ(r.candidate_figures->homotopy, "a-");
  EXPECT_EQ(r.refined_figures->homotopy, "a-");
  for (const models::TrajectorySample& s : r.verified.trajectory.samples) {
    if (s.x > 14.0 && s.x < 16.0) {
      EXPECT_GT(s.y, 9.0) << s.x;  // still north of the block
    }
  }
}

// A small obstacle just north of the straight line, the candidate well north of it: the
// cheaper class is one small step south, which interior-point iterates may take straight
// through the obstacle. The result keeps the candidate's class (first time, or by the corridor
// retry), and the report says whether the corridor was needed.
TEST(CandidateRefiner, KeepsTheClassPastASmallObstacle) {
  terrain::ElevationMap map = testing::flatMap(64, 96);  // 24 m x 16 m
  testing::block(map, 11.5, 8.25, 12.0, 8.75);           // 0.5 m, centred 0.5 m north of y = 8
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  ReferenceFrameOptions options;
  options.anchor = {12.0, 4.0};  // south of the obstacle: its frame points north
  const ReferenceFrames frames =
      ReferenceFrames::build(world->map, terrain::findObstacleClusters(world->map), options);
  ASSERT_EQ(frames.size(), 1u);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r =
      refiner.refine(xyPath({{3.0, 8.0}, {8.0, 9.6}, {16.0, 9.6}, {21.0, 8.0}}));
  expectSound(r, world->problem, frames);
  EXPECT_NE(r.refined_figures->homotopy, "");  // it passes south of the frame's start: crosses
  for (const models::TrajectorySample& s : r.verified.trajectory.samples) {
    if (s.x > 11.5 && s.x < 12.0) {
      EXPECT_GT(s.y, 8.75) << s.x;
    }
  }
  RecordProperty("corridor_radius_m", std::to_string(r.corridor_radius_m));
}

// A wiggly candidate with a loop (as a PRM's first solution can be): the optimiser starts from
// its shortcut path (same class), first on a coarse mesh, and the result is sound.
TEST(CandidateRefiner, AWigglyCandidateStartsFromItsShortcut) {
  terrain::ElevationMap map = testing::flatMap(64, 96);
  testing::block(map, 11.0, 2.0, 13.0, 5.0);  // south of the route: a frame, not in the way
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r = refiner.refine(xyPath({{3.0, 8.0},
                                                    {6.0, 11.0},
                                                    {8.0, 12.0},
                                                    {9.0, 10.0},
                                                    {7.0, 9.5},
                                                    {8.0, 12.5},
                                                    {12.0, 7.0},
                                                    {15.0, 10.0},
                                                    {21.0, 8.0}}));
  expectSound(r, world->problem, frames);
  EXPECT_GT(r.guess_shortcut_m, 3.0);
  EXPECT_GT(r.coarse_intervals, 0);
  EXPECT_LT(r.costRatio(), 0.8);
}

// The shortcut guess holds the pitch and roll limits the candidate held: a candidate round a
// ridge (flanks of 50 deg, limits 0.45 rad) through its gap is not cut straight across it
// (that cut would be 10 m shorter; on the moon DEM such a guess made collocation wander
// to a 368 m, infeasible end).
TEST(CandidateRefiner, TheShortcutDoesNotCrossSlopesBeyondTheLimits) {
  terrain::ElevationMap map = testing::flatMap(64, 96);  // 24 m x 16 m
  terrain::testing::raiseRidge(map, 12.0, 2.0, 1.0, 10.5, 2.0);
  auto world = testing::worldOn(std::move(map), {3.0, 4.0}, {21.0, 4.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r =
      refiner.refine(xyPath({{3.0, 4.0}, {10.0, 14.0}, {14.0, 14.0}, {21.0, 4.0}}));
  EXPECT_LT(r.guess_shortcut_m, 3.0);
  expectSound(r, world->problem, frames);
}

// ... and the ground the speed tables forbid: a ridge of 23 deg flanks, within the pitch limit
// (0.45 rad), is cut straight across without tables, but not for the Segway, whose look-ups
// allow no speed beyond 20 deg (on davosdorf such a cut started its collocation 2 m/s beyond
// the slope bound, and it wandered). Only the guess is asserted: the Segway's solve is cut at
// 5 s.
TEST(CandidateRefiner, TheShortcutKeepsOffGroundTheSpeedTablesForbid) {
  terrain::ElevationMap map = testing::flatMap(64, 96);  // 24 m x 16 m
  terrain::testing::raiseRidge(map, 12.0, 0.7, 1.0, 10.5, 2.0);
  auto world = testing::worldOn(std::move(map), {3.0, 4.0}, {21.0, 4.0});
  const ReferenceFrames frames = framesOf(*world);
  const models::Trajectory candidate =
      xyPath({{3.0, 4.0}, {10.0, 14.0}, {14.0, 14.0}, {21.0, 4.0}});
  ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const RefinementResult without = CandidateRefiner(world->problem, bvp, frames).refine(candidate);
  EXPECT_GT(without.guess_shortcut_m, 3.0);
  const models::SegwayLookups segway = models::defaultSegwayLookups();
  bvp.tables.segway = &segway;
  RefinementOptions options;
  options.time_limit_s = 5.0;
  const RefinementResult with =
      CandidateRefiner(world->problem, bvp, frames, options).refine(candidate);
  EXPECT_LT(with.guess_shortcut_m, 3.0);
}

// A candidate that drives its path about as fast as the limits allow (here a refined
// trajectory, refined again) starts Ipopt's barrier warm and needs fewer iterations than with
// the adaptive barrier, to the same trajectory; refine.warm_start_time_ratio decides. A slow
// candidate (the x,y path's derived profile, which stops at its corners) is solved on the
// coarse mesh first, whose solution starts the fine solve warm; without that coarse solve it
// starts adaptive.
TEST(CandidateRefiner, ANearOptimalCandidateStartsTheBarrierWarm) {
  terrain::ElevationMap map = testing::flatMap(64, 96);
  testing::block(map, 10.0, 9.0, 14.0, 12.0);
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const RefinementResult first = CandidateRefiner(world->problem, bvp, frames)
                                     .refine(xyPath({{3.0, 8.0}, {8.0, 6.0}, {21.0, 8.0}}));
  expectSound(first, world->problem, frames);
  EXPECT_GT(first.coarse_intervals, 0);
  EXPECT_EQ(first.coarse_status, ocp::SolveStatus::kConverged);
  EXPECT_TRUE(first.coarse_used);  // flat ground: nothing between its points it did not see
  EXPECT_LE(first.coarse_limit_excess, 0.0);
  EXPECT_TRUE(first.warm_start);
  const models::Trajectory& candidate = first.verified.trajectory;
  const RefinementResult warm = CandidateRefiner(world->problem, bvp, frames).refine(candidate);
  expectSound(warm, world->problem, frames);
  EXPECT_TRUE(warm.warm_start);
  EXPECT_EQ(warm.coarse_intervals, 0);  // near optimal: straight to the fine mesh
  RefinementOptions options;
  options.warm_start_time_ratio = 1.0;  // it turns: slower than the straight bang-bang bound
  options.coarse_interval_length_m = options.interval_length_m;  // no coarse solve
  const RefinementResult adaptive =
      CandidateRefiner(world->problem, bvp, frames, options).refine(candidate);
  expectSound(adaptive, world->problem, frames);
  EXPECT_EQ(adaptive.coarse_intervals, 0);
  EXPECT_FALSE(adaptive.warm_start);
  EXPECT_LT(warm.iterations, adaptive.iterations);
  RecordProperty("iterations_warm", warm.iterations);
  RecordProperty("iterations_adaptive", adaptive.iterations);
  EXPECT_NEAR(warm.verified.final_time, adaptive.verified.final_time,
              2e-3 * adaptive.verified.final_time);
}

TEST(CandidateRefiner, AutoPicksNewtonForShortClearPathsAndCollocationOtherwise) {
  const RefinementOptions options;
  std::string rule;
  EXPECT_EQ(chooseRefineMethod(options, 6.0, 1e3, 0, rule), RefineMethod::kIpopt);
  EXPECT_THAT(rule, HasSubstr("polynomial"));
  EXPECT_EQ(chooseRefineMethod(options, 25.0, 1e3, 0, rule), RefineMethod::kCollocation);
  EXPECT_THAT(rule, HasSubstr("long"));
  EXPECT_EQ(chooseRefineMethod(options, 6.0, 0.5, 0, rule), RefineMethod::kCollocation);
  EXPECT_THAT(rule, HasSubstr("impassable"));
  EXPECT_EQ(chooseRefineMethod(options, 6.0, 1e3, 5, rule), RefineMethod::kCollocation);
  EXPECT_THAT(rule, HasSubstr("sign"));
  RefinementOptions shooting;
  shooting.method = RefineMethod::kShooting;
  EXPECT_EQ(chooseRefineMethod(shooting, 6.0, 1e3, 0, rule), RefineMethod::kShooting);

  // End to end on open flat ground: a short gentle S-path is refined with polynomial controls.
  auto world = testing::worldOn(testing::flatMap(64, 64), {4.0, 8.0}, {10.0, 9.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r = refiner.refine(xyPath({{4.0, 8.0}, {7.0, 8.3}, {10.0, 9.0}}));
  EXPECT_EQ(r.method, RefineMethod::kIpopt) << r.method_rule;
  expectSound(r, world->problem, frames);
  ASSERT_TRUE(r.parametric.has_value());
}

// The clock says when it decided: a refinement it cut (the parametric solve, the collocation
// that auto would try next, a collocation's rounds) reports time_limit_reached; one that ended
// on its own does not.
TEST(CandidateRefiner, SaysWhenTheClockEndedOrSkippedASolve) {
  auto world = testing::worldOn(testing::flatMap(64, 64), {4.0, 8.0}, {10.0, 9.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const models::Trajectory s_path = xyPath({{4.0, 8.0}, {7.0, 8.3}, {10.0, 9.0}});
  const RefinementResult ample = CandidateRefiner(world->problem, bvp, frames).refine(s_path);
  EXPECT_EQ(ample.status, ocp::SolveStatus::kConverged) << ample.reason;
  EXPECT_FALSE(ample.time_limit_reached);

  RefinementOptions none;
  none.time_limit_s = 0.0;
  const RefinementResult cut = CandidateRefiner(world->problem, bvp, frames, none).refine(s_path);
  EXPECT_NE(cut.status, ocp::SolveStatus::kConverged);
  EXPECT_TRUE(cut.time_limit_reached) << cut.method_rule << ": " << cut.reason;
  EXPECT_EQ(cut.method, RefineMethod::kIpopt) << cut.method_rule;  // collocation skipped

  RefinementOptions collocation = none;
  collocation.method = RefineMethod::kCollocation;
  const RefinementResult cut_collocation =
      CandidateRefiner(world->problem, bvp, frames, collocation).refine(s_path);
  EXPECT_NE(cut_collocation.status, ocp::SolveStatus::kConverged);
  EXPECT_TRUE(cut_collocation.time_limit_reached) << cut_collocation.reason;
}

TEST(CandidateRefiner, UnusableCandidatesAreErrorsNamingTheSample) {
  auto world = testing::worldOn(testing::flatMap(64, 64), {4.0, 8.0}, {10.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames;
  const CandidateRefiner refiner(world->problem, bvp, frames);

  const RefinementResult single = refiner.refine(xyPath({{4.0, 8.0}}));
  EXPECT_EQ(single.status, ocp::SolveStatus::kError);
  EXPECT_THAT(single.reason, HasSubstr("single point"));
  const RefinementResult same = refiner.refine(xyPath({{4.0, 8.0}, {4.0, 8.0}, {4.0, 8.0}}));
  EXPECT_EQ(same.status, ocp::SolveStatus::kError);
  EXPECT_THAT(same.reason, HasSubstr("single point"));

  const RefinementResult off = refiner.refine(xyPath({{4.0, 8.0}, {7.0, 30.0}, {10.0, 8.0}}));
  EXPECT_EQ(off.status, ocp::SolveStatus::kError);
  EXPECT_THAT(off.reason, HasSubstr("row 2"));
  EXPECT_THAT(off.reason, HasSubstr("leaves the map"));

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const RefinementResult not_finite = refiner.refine(xyPath({{4.0, 8.0}, {nan, 8.0}}));
  EXPECT_EQ(not_finite.status, ocp::SolveStatus::kError);
  EXPECT_THAT(not_finite.reason, HasSubstr("row 2"));

  RefinementOptions bad;
  bad.interval_length_m = 0.0;
  const CandidateRefiner bad_refiner(world->problem, bvp, frames, bad);
  const RefinementResult r = bad_refiner.refine(xyPath({{4.0, 8.0}, {10.0, 8.0}}));
  EXPECT_EQ(r.status, ocp::SolveStatus::kError);
  EXPECT_THAT(r.reason, HasSubstr("interval_length_m"));
}

// A candidate straight through an obstacle: measured and reported (its check names the lethal
// cells), and its refinement fails with Ipopt's reason: started inside the obstacle, the
// clearance constraint is locally infeasible. Nothing claims it converged.
TEST(CandidateRefiner, ACandidateThroughLethalCellsIsReportedWithTheReason) {
  terrain::ElevationMap map = testing::flatMap(64, 96);
  testing::block(map, 11.0, 7.0, 13.0, 9.0);  // on the straight line
  auto world = testing::worldOn(std::move(map), {3.0, 8.0}, {21.0, 8.0});
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  const CandidateRefiner refiner(world->problem, bvp, frames);
  const RefinementResult r = refiner.refine(xyPath({{3.0, 8.0}, {12.0, 8.3}, {21.0, 8.0}}));
  ASSERT_TRUE(r.candidate_figures.has_value());
  EXPECT_FALSE(r.candidate_figures->check.ok());
  EXPECT_THAT(r.candidate_figures->check.summary(), HasSubstr("lethal"));
  EXPECT_EQ(r.status, ocp::SolveStatus::kInfeasible) << r.reason;
  EXPECT_THAT(r.reason, HasSubstr("infeasible"));
}

TEST(CandidateRefiner, AFailedSolveKeepsTheCandidateAndSaysWhy) {
  auto world = testing::makeWorld(terrain::TerrainKind::kHills, 96, 2);
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  RefinementOptions options;
  options.method = RefineMethod::kCollocation;
  options.transcription.max_iterations = 2;
  const CandidateRefiner refiner(world->problem, bvp, frames, options);
  const Eigen::Vector2d a = world->problem.start.position, b = world->problem.goal.position;
  const RefinementResult r = refiner.refine(xyPath({a, 0.5 * (a + b) + Eigen::Vector2d(0, 3), b}));
  EXPECT_EQ(r.status, ocp::SolveStatus::kMaxIterations) << r.reason;
  EXPECT_FALSE(r.reason.empty());
  ASSERT_TRUE(r.candidate_figures.has_value());
  EXPECT_GT(r.candidate_figures->cost, 0.0);
  // Two on the coarse mesh (the x,y path's derived profile is slow), two on the fine one.
  EXPECT_GT(r.coarse_intervals, 0);
  EXPECT_EQ(r.iterations, 4);
}

// The exact minimum-time trajectory along the straight line from the world's start to its goal
// (both at rest, heading east): full acceleration, cruise at v_max, full braking, at the limits.
models::Trajectory bangBangLine(const PlanningProblem& p) {
  const double a = p.limits.a_max, v_max = p.limits.v_max;
  const double distance = (p.goal.position - p.start.position).norm();
  const double v_peak = std::min(v_max, std::sqrt(a * distance));
  const double t_ramp = v_peak / a;
  const double t_cruise = (distance - v_peak * t_ramp) / v_peak;
  const double total = 2.0 * t_ramp + t_cruise;
  models::Trajectory t;
  for (models::TrajectoryColumn c :
       {models::TrajectoryColumn::kT, models::TrajectoryColumn::kX, models::TrajectoryColumn::kY,
        models::TrajectoryColumn::kHeading, models::TrajectoryColumn::kV,
        models::TrajectoryColumn::kOmega, models::TrajectoryColumn::kCurvature}) {
    t.has_column[static_cast<std::size_t>(c)] = true;
  }
  const int steps = static_cast<int>(std::ceil(total / 0.02));
  for (int k = 0; k <= steps; ++k) {
    const double time = total * k / steps;
    double s = 0.0, v = 0.0;
    if (time < t_ramp) {
      v = a * time;
      s = 0.5 * a * time * time;
    } else if (time < t_ramp + t_cruise) {
      v = v_peak;
      s = 0.5 * v_peak * t_ramp + v_peak * (time - t_ramp);
    } else {
      const double left = std::max(total - time, 0.0);
      v = a * left;
      s = distance - 0.5 * a * left * left;
    }
    models::TrajectorySample sample = models::TrajectorySample::unknown();
    sample.t = time;
    sample.x = p.start.position.x() + s;
    sample.y = p.start.position.y();
    sample.heading = 0.0;
    sample.v = v;
    sample.omega = 0.0;
    sample.curvature = 0.0;
    t.samples.push_back(sample);
  }
  return t;
}

// A slow candidate along a good path (the straight line at half the speed, as a PRM's first
// solution drives a path near its shortest): the optimiser starts from the path re-timed by the
// speed pass (at 0.8 of the limits: about 1.25 x the minimum time instead of 2 x), solved on
// the coarse mesh and then warm on the fine one, and ends at the minimum time along the line.
TEST(CandidateRefiner, ASlowCandidateOnAGoodPathStartsFromItsPathRetimed) {
  auto world = testing::makeWorld(terrain::TerrainKind::kFlat, 96, 1);
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  const ReferenceFrames frames = framesOf(*world);
  RefinementOptions options;
  options.method = RefineMethod::kCollocation;
  const CandidateRefiner refiner(world->problem, bvp, frames, options);
  models::Trajectory slow = bangBangLine(world->problem);
  const double fastest = slow.samples.back().t;
  for (models::TrajectorySample& sample : slow.samples) {
    sample.t *= 2.0;
    sample.v *= 0.5;
  }
  const RefinementResult r = refiner.refine(slow);
  expectSound(r, world->problem, frames);
  EXPECT_NEAR(r.guess_retimed_s, 0.75 * fastest, 0.05 * fastest);
  EXPECT_EQ(r.guess_shortcut_m, 0.0);
  EXPECT_GT(r.coarse_intervals, 0);
  EXPECT_TRUE(r.warm_start);
  EXPECT_NEAR(r.verified.final_time, fastest, 0.01 * fastest);
}

// A refinement that ends worse than its feasible candidate is not `converged`: the candidate is
// returned, and the reason says so. The candidate here is already the exact optimum (at the
// limits), the refinement solves within its margins: a little slower, and worse_tolerance 0
// counts any loss.
TEST(CandidateRefiner, ARefinementWorseThanItsFeasibleCandidateReturnsTheCandidate) {
  auto world = testing::makeWorld(terrain::TerrainKind::kFlat, 96, 1);
  ASSERT_NEAR(world->problem.start.position.y(), world->problem.goal.position.y(), 1e-12);
  const ocp::BoundaryValueProblem bvp = bvpOf(world->problem);
  RefinementOptions options;
  options.method = RefineMethod::kCollocation;
  options.worse_tolerance = 0.0;
  const ReferenceFrames frames = framesOf(*world);  // the refiner keeps a reference
  const CandidateRefiner refiner(world->problem, bvp, frames, options);
  const RefinementResult r = refiner.refine(bangBangLine(world->problem));
  ASSERT_TRUE(r.candidate_figures.has_value());
  EXPECT_TRUE(r.candidate_figures->check.ok()) << r.candidate_figures->check.summary();
  ASSERT_TRUE(r.refined_figures.has_value()) << r.reason;
  EXPECT_GT(r.refined_figures->cost, r.candidate_figures->cost);
  EXPECT_TRUE(r.returned_candidate) << r.reason;
  EXPECT_EQ(r.status, ocp::SolveStatus::kDiverged);
  EXPECT_THAT(r.reason, HasSubstr("the candidate is returned"));
}

}  // namespace
}  // namespace terratraj::search
