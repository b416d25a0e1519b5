#include "terratraj/search/bang_bang_bound.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "terratraj/search/speed_profile.hpp"

namespace terratraj::search {
namespace {

TEST(BangBangBound, KnownProfiles) {
  // v_max 1 m/s, a_max 0.5 m/s^2: reaching 1 m/s takes 2 s and 1 m.
  EXPECT_DOUBLE_EQ(bangBangTime(1.0, 0.0, 0.0, 1.0, 1.0, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(bangBangTime(3.0, 0.0, 0.0, 1.0, 1.0, 0.5), 4.0);  // + 2 m cruise
  EXPECT_DOUBLE_EQ(bangBangTime(2.0, 0.0, 0.0, 0.0, 1.0, 0.5), 4.0);  // accelerate, brake
  EXPECT_DOUBLE_EQ(bangBangTime(4.0, 0.0, 0.0, 0.0, 1.0, 0.5), 6.0);  // + 2 m cruise
  EXPECT_DOUBLE_EQ(bangBangTime(0.0, 1.0, 1.0, 1.0, 1.0, 0.5), 0.0);
  // Too short to brake from 1 m/s to 0: the bound is the braking time (a longer path).
  EXPECT_DOUBLE_EQ(bangBangTime(0.1, 1.0, 0.0, 0.0, 1.0, 0.5), 2.0);
  // Too short to reach 1 m/s from rest: the acceleration time.
  EXPECT_DOUBLE_EQ(bangBangTime(0.1, 0.0, 1.0, 1.0, 1.0, 0.5), 2.0);
  EXPECT_EQ(bangBangTime(1.0, 0.0, 0.0, 1.0, 1.0, 0.0), std::numeric_limits<double>::infinity());
}

// The bound equals the time of the bang-bang speed profile along a straight line whenever that
// profile reaches the wished end speed (an independent computation: SpeedProfile's passes).
TEST(BangBangBound, MatchesTheSpeedProfileOnAStraightLine) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SpeedProfile profile;
  int compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double v_max = 0.5 + 2.0 * unit(rng), a_max = 0.2 + unit(rng);
    const double distance = 0.05 + 10.0 * unit(rng);
    const double v0 = v_max * unit(rng), v_end = v_max * unit(rng);
    const int n = 2000;
    std::vector<double> lengths(n, distance / n), caps(n + 1, v_max);
    if (profile.compute(lengths, caps, v0, v_end, a_max) != SpeedProfileStatus::kOk) continue;
    if (std::abs(profile.speeds().back() - v_end) > 1e-9) continue;
    ++compared;
    // The discrete profile clips the peak inside one segment: slightly slower, never faster.
    const double bound = bangBangTime(distance, v0, v_end, v_end, v_max, a_max);
    EXPECT_LE(bound, profile.duration() * (1 + 1e-12));
    EXPECT_NEAR(bound, profile.duration(), 1e-4 * profile.duration())
        << "d " << distance << " v0 " << v0 << " v_end " << v_end;
  }
  EXPECT_GT(compared, 100);
}

TEST(BangBangBound, GoalBoundUsesTheTolerances) {
  const BangBangBound bound(1.0, 0.5);
  GoalRegion goal;
  goal.position = {10.0, 0.0};
  goal.position_tolerance = 1.0;
  goal.v = 0.0;
  goal.speed_tolerance = 0.1;
  PlannerState from;
  EXPECT_DOUBLE_EQ(bound.toGoal(from, goal), bangBangTime(9.0, 0.0, 0.0, 0.1, 1.0, 0.5));
  from.position = {9.5, 0.0};
  from.v = 0.05;
  EXPECT_DOUBLE_EQ(bound.toGoal(from, goal), 0.0);
}

}  // namespace
}  // namespace terratraj::search
