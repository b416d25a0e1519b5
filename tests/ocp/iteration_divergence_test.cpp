// IterationDivergence: when a blown-up interior-point solve stops.
#include "terratraj/ocp/iteration_divergence.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace terratraj::ocp {
namespace {

TEST(IterationDivergence, StopsAfterWindowIterationsInARowAboveTheThreshold) {
  IterationDivergence watch({3, 1e10, 1e14});
  EXPECT_FALSE(watch.diverged(1e11));
  EXPECT_FALSE(watch.diverged(1e12));
  EXPECT_FALSE(watch.diverged(1e9));  // back below: the run starts again
  EXPECT_FALSE(watch.diverged(1e11));
  EXPECT_FALSE(watch.diverged(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(watch.diverged(1e13));
}

TEST(IterationDivergence, StopsAtOnceAboveTheBlowUp) {
  IterationDivergence watch({20, 1e10, 1e12});
  EXPECT_FALSE(watch.diverged(1e3));
  EXPECT_FALSE(watch.diverged(1e12));  // at the blow-up: not above it
  EXPECT_FALSE(watch.diverged(std::numeric_limits<double>::quiet_NaN()));  // in the window only
  EXPECT_TRUE(watch.diverged(1.0001e12));
  IterationDivergence fresh({20, 1e10, 1e12});
  EXPECT_TRUE(fresh.diverged(6e15));  // the first iteration suffices
}

TEST(IterationDivergence, AWindowOfZeroNeverStops) {
  IterationDivergence watch({0, 1e10});
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(watch.diverged(1e20));
}

}  // namespace
}  // namespace terratraj::ocp
