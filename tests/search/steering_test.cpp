// The continuous-curvature steering and its integration on tangent-plane patches.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "search_fixtures.hpp"
#include "terratraj/search/bang_bang_bound.hpp"
#include "terratraj/search/extension_integrator.hpp"

namespace terratraj::search {
namespace {

using testing::makeWorld;
using testing::TestWorld;
constexpr double kPi = 3.14159265358979323846;

// Every sample of a successful extension within the limits, by finite differences.
void expectWithinLimits(const Extension& e, const models::VehicleLimits& l, double sharpness_max) {
  const double eps = 1e-9;
  for (std::size_t i = 0; i < e.points.size(); ++i) {
    const PathPoint& p = e.points[i];
    EXPECT_LE(std::abs(p.curvature), l.kappa_max + eps) << i;
    EXPECT_LE(p.v, l.v_max + eps) << i;
    EXPECT_GE(p.v, -eps) << i;
    EXPECT_LE(std::abs(p.v * p.curvature), l.omega_max + eps) << i;
    if (i == 0) continue;
    const PathPoint& q = e.points[i - 1];
    const double dt = p.t - q.t, ds = p.s - q.s;
    ASSERT_GT(dt, 0.0);
    EXPECT_LE(std::abs(p.v - q.v) / dt, l.a_max * (1 + 1e-9)) << i;
    EXPECT_LE(std::abs(p.curvature - q.curvature) / dt, l.sigma_max * (1 + 1e-9)) << i;
    EXPECT_LE(std::abs(p.curvature - q.curvature) / ds, sharpness_max * (1 + 1e-9)) << i;
  }
}

TEST(ContinuousCurvatureSteering, ReachesTargetsWithinTheLimitsAndAboveTheBound) {
  const std::unique_ptr<TestWorld> world = makeWorld(terrain::TerrainKind::kFlat, 200);
  PlanningProblem& problem = world->problem;
  problem.limits.kappa_max = 1.0;
  problem.limits.sigma_max = 0.5;
  problem.limits.omega_max = 0.8;
  ExtensionIntegrator integrator(problem, {0.125, 0.5});
  const ContinuousCurvatureSteering steering(problem.limits);
  const BangBangBound bound(problem.limits.v_max, problem.limits.a_max);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Extension e;
  int reached = 0;
  for (int trial = 0; trial < 200; ++trial) {
    PlannerState from;
    from.position = {25.0, 25.0};
    from.heading = (2 * unit(rng) - 1) * kPi;
    from.v = problem.limits.v_max * unit(rng);
    const double k_max =
        std::min(problem.limits.kappa_max, problem.limits.omega_max / std::max(from.v, 1e-9));
    from.curvature = (2 * unit(rng) - 1) * k_max;
    const double angle = (2 * unit(rng) - 1) * kPi, range = 4.0 + 12.0 * unit(rng);
    ExtensionRequest request;
    request.target = from.position + range * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    request.target_speed = problem.limits.v_max * unit(rng);
    request.turn_speed = problem.limits.v_max * unit(rng);
    request.max_length = 100.0;
    const ExtensionStatus status = integrator.extend(from, request, e);
    if (status == ExtensionStatus::kUnreachable || status == ExtensionStatus::kSpeed) continue;
    ASSERT_EQ(status, ExtensionStatus::kReached) << extensionStatusName(status);
    ++reached;
    EXPECT_LE((e.end.position - request.target).norm(), 0.5 * 0.125 + 1e-9);
    const TurnShape turn = steering.turnShape(from.v, from.curvature, request.turn_speed);
    expectWithinLimits(e, problem.limits, turn.sharpness);
    EXPECT_DOUBLE_EQ(e.points.front().v, from.v);
    EXPECT_NEAR(e.points.front().curvature, from.curvature, 1e-12);
    // The bang-bang bound to where the extension really ended is a lower bound of its time.
    const double lower = bound.toPoint(from, e.end.position, e.end.v, e.end.v);
    EXPECT_LE(lower, e.duration * (1 + 1e-9) + 1e-12) << trial;
  }
  EXPECT_GT(reached, 150);
}

// On flat ground a left turn from rest toward a target at 90 degrees is a clothoid, an arc,
// an anti-clothoid and a line: the curvature rises, holds, falls to 0 and stays there.
TEST(ContinuousCurvatureSteering, TurnIsClothoidArcAntiClothoidLine) {
  const std::unique_ptr<TestWorld> world = makeWorld(terrain::TerrainKind::kFlat, 200);
  PlanningProblem& problem = world->problem;
  problem.limits.kappa_max = 0.8;
  problem.limits.sigma_max = 0.5;
  ExtensionIntegrator integrator(problem, {0.05, 0.5});
  PlannerState from;
  from.position = {20.0, 20.0};
  ExtensionRequest request;
  request.target = {22.0, 32.0};
  request.target_speed = 0.5;
  request.turn_speed = 0.5;
  request.max_length = 100.0;
  Extension e;
  ASSERT_EQ(integrator.extend(from, request, e), ExtensionStatus::kReached);
  int phase = 0;  // 0 rising, 1 arc, 2 falling, 3 line
  const double tiny = 1e-9;
  double peak = 0.0;
  for (std::size_t i = 1; i < e.points.size(); ++i) {
    const double dk = e.points[i].curvature - e.points[i - 1].curvature;
    const double k = e.points[i].curvature;
    peak = std::max(peak, k);
    if (phase == 3) {
      // On the line: at most one-step corrections of the bearing.
      EXPECT_LE(std::abs(k), 1.0 * 0.05 + tiny) << "sample " << i;
      continue;
    }
    const int now = dk > tiny ? 0 : (dk < -tiny ? 2 : (std::abs(k) < 1e-6 ? 3 : 1));
    EXPECT_GE(now, phase) << "sample " << i << " kappa " << k;
    phase = std::max(phase, now);
  }
  EXPECT_EQ(phase, 3);
  EXPECT_NEAR(peak, 0.8, 1e-9);  // the arc at the turn curvature (min(kappa_max, omega/v))
  // Ends aligned with the line to the target.
  EXPECT_NEAR(e.points.back().curvature, 0.0, 1e-6);
}

TEST(ExtensionIntegrator, TrapsOnLethalCellsSteepSlopesAndUnreachableTargets) {
  std::unique_ptr<TestWorld> world = makeWorld(terrain::TerrainKind::kFlat, 120);
  terrain::GridLayer& lethal = world->map.addLayer(terrain::layer_names::kLethal, 0.0f);
  for (int row = 0; row < 120; ++row) lethal(row, 60) = 1.0f;  // a wall at x = 15 m
  ExtensionIntegrator integrator(world->problem, {0.125, 0.5});
  PlannerState from;
  from.position = {10.0, 15.0};
  from.v = 0.5;
  ExtensionRequest request;
  request.target = {20.0, 15.0};
  request.target_speed = request.turn_speed = 0.5;
  request.max_length = 30.0;
  Extension e;
  EXPECT_EQ(integrator.extend(from, request, e), ExtensionStatus::kLethal);
  // A target inside the turning circle: a tight target to the side at full speed.
  std::unique_ptr<TestWorld> open = makeWorld(terrain::TerrainKind::kFlat, 200);
  open->problem.limits.kappa_max = 0.2;
  ExtensionIntegrator slow_turner(open->problem, {0.125, 0.5});
  PlannerState fast;
  fast.position = {25.0, 25.0};
  fast.v = 1.0;
  request.target = {25.5, 26.0};
  EXPECT_EQ(slow_turner.extend(fast, request, e), ExtensionStatus::kUnreachable);
  // Off the map.
  request.target = {-5.0, 15.0};
  world->problem.limits.kappa_max = 1.0;
  ExtensionIntegrator again(world->problem, {0.125, 0.5});
  from.heading = kPi;
  EXPECT_EQ(again.extend(from, request, e), ExtensionStatus::kOffMap);

  // A ramp steeper than pitch_max.
  std::unique_ptr<TestWorld> ramp = makeWorld(terrain::TerrainKind::kRamp, 120);
  ramp->problem.limits.pitch_max = 0.01;
  ramp->problem.limits.roll_max = 0.01;
  ExtensionIntegrator on_ramp(ramp->problem, {0.125, 0.5});
  from = PlannerState{};
  from.position = {15.0, 15.0};
  request.target = {25.0, 15.0};
  const ExtensionStatus status = on_ramp.extend(from, request, e);
  EXPECT_TRUE(status == ExtensionStatus::kPitch || status == ExtensionStatus::kRoll)
      << extensionStatusName(status);
}

TEST(ExtensionIntegrator, SameInputSameExtension) {
  const std::unique_ptr<TestWorld> world = makeWorld(terrain::TerrainKind::kHills, 128);
  ExtensionIntegrator a(world->problem, {0.125, 0.5});
  PlannerState from;
  from.position = {10.0, 16.0};
  from.v = 0.3;
  from.curvature = 0.2;
  ExtensionRequest request;
  request.target = {16.0, 12.0};
  request.target_speed = 0.8;
  request.turn_speed = 0.6;
  Extension first, second, other;
  a.extend(from, request, first);
  a.extend(from, {{4.0, 25.0}, 0.1, 0.1, 6.0}, other);  // state left behind must not matter
  a.extend(from, request, second);
  ASSERT_EQ(first.points.size(), second.points.size());
  for (std::size_t i = 0; i < first.points.size(); ++i) {
    EXPECT_EQ(first.points[i].position, second.points[i].position);
    EXPECT_EQ(first.points[i].v, second.points[i].v);
  }
}

}  // namespace
}  // namespace terratraj::search
