// IterationStall: when a cycling interior-point solve may stop as converged.
#include "terratraj/ocp/iteration_stall.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace terratraj::ocp {
namespace {

// The cycle measured on davosdorf (docs/benchmarks.md): full steps between two points whose
// costs agree to 6e-6, the constraints met on one and missed by 5e-4 on the other, the dual
// infeasibility near 7e-4.
struct Iterate {
  double cost, violation, dual, mu;
};
constexpr Iterate kFeasible{12.3232002, 5e-9, 7.0e-4, 1e-9};
constexpr Iterate kMissed{12.3231342, 5e-4, 7.9e-4, 1e-9};

bool feed(IterationStall& stall, const Iterate& it) {
  return stall.accept(it.cost, it.violation, it.dual, it.mu);
}

TEST(IterationStall, AcceptsACycleAtItsFeasibleIterateOnceTheWindowIsFull) {
  StallAcceptance acceptance;
  acceptance.window = 6;
  IterationStall stall(acceptance);
  int accepted_at = -1;
  for (int i = 0; i < 20 && accepted_at < 0; ++i) {
    if (feed(stall, i % 2 == 0 ? kMissed : kFeasible)) accepted_at = i;
  }
  // At the first feasible iterate with the window full (the 6th), never at an infeasible one.
  EXPECT_EQ(accepted_at, 5);
  EXPECT_EQ(stall.iterations(), 6);
}

TEST(IterationStall, NeverAcceptsWhileTheCostMoves) {
  IterationStall stall(StallAcceptance{});
  for (int i = 0; i < 200; ++i) {
    // Feasible and nearly stationary, but still going down by 1e-4 of the cost an iteration.
    EXPECT_FALSE(stall.accept(20.0 * std::pow(1.0 - 1e-4, i), 0.0, 1e-4, 1e-9)) << i;
  }
}

TEST(IterationStall, EachConditionAloneBlocksIt) {
  const Iterate blocked[] = {
      {kFeasible.cost, 2e-6, kFeasible.dual, kFeasible.mu},         // constraints missed
      {kFeasible.cost, kFeasible.violation, 0.05, kFeasible.mu},    // far from stationary
      {kFeasible.cost, kFeasible.violation, kFeasible.dual, 1e-3},  // barrier still large
      {std::numeric_limits<double>::quiet_NaN(), kFeasible.violation, kFeasible.dual, kFeasible.mu},
  };
  for (const Iterate& last : blocked) {
    IterationStall fresh(StallAcceptance{});
    for (int i = 0; i < 39; ++i) feed(fresh, kFeasible);
    EXPECT_FALSE(feed(fresh, last))
        << last.cost << " " << last.violation << " " << last.dual << " " << last.mu;
  }
  // The same window with a feasible, stationary last iterate is accepted.
  IterationStall stall(StallAcceptance{});
  for (int i = 0; i < 39; ++i) feed(stall, kFeasible);
  EXPECT_TRUE(feed(stall, kFeasible));
}

TEST(IterationStall, AWindowOfZeroTurnsItOff) {
  StallAcceptance off;
  off.window = 0;
  IterationStall stall(off);
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(feed(stall, kFeasible));
}

}  // namespace
}  // namespace terratraj::ocp
