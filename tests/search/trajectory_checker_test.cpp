#include "terratraj/search/trajectory_checker.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "search_fixtures.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"

namespace terratraj::search {
namespace {

bool hasViolation(const CheckReport& report, const std::string& limit) {
  for (const CheckViolation& v : report.violations) {
    if (v.limit == limit) return true;
  }
  return false;
}

// The checker must catch each kind of broken trajectory, or the planner tests prove nothing.
TEST(TrajectoryChecker, CatchesEachInjectedViolation) {
  std::unique_ptr<testing::TestWorld> world = testing::makeWorld(terrain::TerrainKind::kFlat, 96);
  KinodynamicPrm planner(world->problem);
  const PlanResult result = planner.solve(TerminationCondition::timeLimit(0.2));
  ASSERT_EQ(result.status, PlanStatus::kSolved);
  const TrajectoryChecker checker(world->problem);
  ASSERT_TRUE(checker.check(result.trajectory).ok());
  const std::size_t mid = result.trajectory.samples.size() / 2;
  const auto broken = [&](auto change) {
    models::Trajectory t = result.trajectory;
    change(t.samples[mid]);
    return checker.check(t);
  };
  const double v_max = world->problem.limits.v_max;
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.v = 1.5 * v_max; }), "v_max"));
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.v = 1.5 * v_max; }), "a_max"));
  EXPECT_TRUE(
      hasViolation(broken([&](auto& s) { s.curvature = 3.0, s.omega = s.v * 3.0; }), "kappa_max"));
  EXPECT_TRUE(hasViolation(
      broken([&](auto& s) { s.curvature += 0.5, s.omega = s.v * s.curvature; }), "sigma_max"));
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.omega += 0.1; }), "omega_equals_v_curvature"));
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.y += 1.0; }), "motion"));
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.pitch += 0.1; }), "pitch_column"));
  EXPECT_TRUE(hasViolation(broken([&](auto& s) { s.t = -1.0; }), "time_order"));
  models::Trajectory short_of_goal = result.trajectory;
  short_of_goal.samples.pop_back();
  short_of_goal.samples.pop_back();
  short_of_goal.samples.pop_back();
  short_of_goal.samples.pop_back();
  short_of_goal.samples.pop_back();
  const CheckReport short_report = checker.check(short_of_goal);
  EXPECT_TRUE(hasViolation(short_report, "goal_position") ||
              hasViolation(short_report, "goal_heading") ||
              hasViolation(short_report, "goal_speed"))
      << short_report.summary();
  // The verdict names a missed goal beside a broken limit, which it reports first.
  models::Trajectory short_and_fast = short_of_goal;
  short_and_fast.samples[mid].v = 1.5 * world->problem.limits.v_max;
  const models::TrajectoryVerdict verdict =
      models::judgeTrajectory(short_and_fast, requirementsOf(world->problem));
  EXPECT_EQ(verdict.failure, models::VerdictFailure::kBreaksLimits) << verdict.reason;
  EXPECT_TRUE(verdict.misses_goal) << verdict.reason;
  EXPECT_FALSE(
      models::judgeTrajectory(result.trajectory, requirementsOf(world->problem)).misses_goal);
  // A lethal cell under the path.
  terrain::GridLayer& lethal = world->map.addLayer(terrain::layer_names::kLethal, 0.0f);
  const models::TrajectorySample& s = result.trajectory.samples[mid];
  lethal(*world->map.geometry().cellAt({s.x, s.y})) = 1.0f;
  EXPECT_TRUE(hasViolation(checker.check(result.trajectory), "lethal"));
  // A steeper limit than the path's attitude.
  world->problem.limits.v_max = 0.5 * v_max;
  EXPECT_TRUE(hasViolation(checker.check(result.trajectory), "v_max"));
}

// Clothoid S-bends (curvature +1 to -1 1/m linearly over 1.5 m, and back) written as rows 1.5 m
// apart, as the PRM writes its patches on a 3 m DEM: the chord leaves the end headings' range, but
// by less than the arc's own heading excursion, so the heading of motion holds. The same rows
// with a curvature that keeps its sign (no excursion possible) break it.
TEST(TrajectoryChecker, AcceptsAClothoidSBendBetweenSparseRows) {
  std::unique_ptr<testing::TestWorld> world = testing::makeWorld(terrain::TerrainKind::kFlat, 96);
  world->problem.limits.kappa_max = 1.0;
  world->problem.limits.sigma_max = 1.0;
  const double v = 0.5, length = 1.5;
  const auto curvature = [&](double s) {
    return s < length ? 1.0 - 2.0 * s / length : -1.0 + 2.0 * (s - length) / length;
  };
  models::Trajectory s_bend;
  s_bend.has_column.fill(true);
  double x = 4.0, y = 12.0, heading = 0.0;
  const int steps = 3000;
  const double ds = 2.0 * length / steps;
  for (int k = 0; k <= steps; ++k) {
    const double s = k * ds;
    const double kappa = curvature(s);
    if (k % (steps / 2) == 0) {
      models::TrajectorySample row;
      row.t = s / v;
      row.x = x, row.y = y, row.heading = heading;
      row.v = v, row.curvature = kappa, row.omega = v * kappa;
      s_bend.samples.push_back(row);
    }
    // Midpoint rule on the heading, exact position increments for a short step.
    const double mid_heading = heading + 0.5 * ds * kappa;
    x += ds * std::cos(mid_heading);
    y += ds * std::sin(mid_heading);
    heading += ds * curvature(s + 0.5 * ds);
  }
  ASSERT_EQ(s_bend.samples.size(), 3u);
  const TrajectoryChecker checker(world->problem);
  const CheckReport report = checker.check(s_bend, false);
  EXPECT_FALSE(hasViolation(report, "heading_of_motion")) << report.summary();
  models::Trajectory straight_claimed = s_bend;
  for (models::TrajectorySample& row : straight_claimed.samples) row.curvature = row.omega = 0.0;
  EXPECT_TRUE(hasViolation(checker.check(straight_claimed, false), "heading_of_motion"));
}

}  // namespace
}  // namespace terratraj::search
