#include "terratraj/ocp/dubins_path.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dubins_length.hpp"

namespace terratraj::ocp {
namespace {

// Every word returned ends at the goal pose, its samples are continuous with curvature within
// 1 / radius, and the shortest agrees with the reference length of the tests.
TEST(DubinsPath, EveryWordReachesTheGoalAndTheShortestIsTheReference) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-8.0, 8.0), angle(-3.14159, 3.14159);
  for (int trial = 0; trial < 200; ++trial) {
    const PlanePose from{coordinate(rng), coordinate(rng), angle(rng)};
    const PlanePose to{coordinate(rng), coordinate(rng), angle(rng)};
    const double radius = 0.5 + 0.01 * trial;
    const std::vector<DubinsPath> paths = dubinsPaths(from, to, radius);
    ASSERT_FALSE(paths.empty());
    EXPECT_NEAR(paths.front().length(),
                testing::dubinsLength(from.x, from.y, from.heading, to.x, to.y, to.heading, radius),
                1e-6);
    for (const DubinsPath& p : paths) {
      const std::vector<PathPoint2> points = p.sample(0.05);
      EXPECT_NEAR(points.front().x, from.x, 1e-9);
      EXPECT_NEAR(points.back().x, to.x, 1e-6);
      EXPECT_NEAR(points.back().y, to.y, 1e-6);
      EXPECT_NEAR(std::remainder(points.back().heading - to.heading, 2 * M_PI), 0.0, 1e-6);
      for (std::size_t i = 1; i < points.size(); ++i) {
        const double ds = points[i].s - points[i - 1].s;
        EXPECT_LE(std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y),
                  ds + 1e-9);
        EXPECT_LE(std::abs(points[i].curvature), 1.0 / radius + 1e-12);
      }
    }
  }
}

// A U-turn at the same position is a loop, not "start and goal coincide".
TEST(DubinsPath, AUTurnInPlaceIsALoop) {
  const std::vector<DubinsPath> paths = dubinsPaths({0, 0, 0}, {0, 0, M_PI}, 1.0);
  ASSERT_FALSE(paths.empty());
  EXPECT_GT(paths.front().length(), M_PI);
}

// The reference length the transcription tests compare with.
TEST(DubinsReference, KnownLengths) {
  EXPECT_NEAR(testing::dubinsLength(0, 0, 0, 10, 0, 0, 1.0), 10.0, 1e-9);
  EXPECT_NEAR(testing::dubinsLength(0, 0, 0, 1, 1, M_PI / 2, 1.0), M_PI / 2, 1e-9);
  EXPECT_NEAR(testing::dubinsLength(0, 0, 0, 0, 2, M_PI, 1.0), M_PI, 1e-9);
  EXPECT_NEAR(testing::dubinsLength(0, 0, 0, 0, -2, M_PI, 1.0), M_PI, 1e-9);
  EXPECT_NEAR(testing::dubinsLength(0, 0, 0, 5, 1, 0, 1.0),
              testing::dubinsLength(0, 0, 0, 5, -1, 0, 1.0), 1e-9);  // mirror
}

}  // namespace
}  // namespace terratraj::ocp
