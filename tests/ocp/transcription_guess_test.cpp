// Guesses from a geometric path: the speed profile under the limits and, given the vehicle, under
// the problem's speed tables at the vehicle's attitude (the Segway's look-ups by slope).
#include "terratraj/ocp/transcription_guess.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../terrain/test_maps.hpp"
#include "segway_problems.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::ocp {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// A plane rising along x at `slope` [rad] over 40 m x 10 m at 0.25 m.
terrain::ElevationMap rampMap(double slope) {
  return terrain::testing::planeMap(40, 160, 0.25, std::tan(slope), 0.0, 0.0);
}

// The Segway's problem: rest to rest 30 m up the ramp (heading 0), its paper's limits.
BoundaryValueProblem segwayUpTheRamp(const models::SegwayLookups& lookups) {
  return testing::segwayAlongX(lookups, 34.0, 30.0 * kDegree);
}

double largestSpeed(const TranscriptionGuess& guess) {
  double v = 0.0;
  for (const PointVector& p : guess.points) v = std::max(v, p(3));
  return v;
}

// Up a 12 deg ramp the Segway's look-ups allow about 2.0 m/s and 0.98 m/s^2 (docs/segway-rmp.md):
// the guess given the vehicle keeps within 0.8 of both at every sample; without it, the guess
// knows only v_max and a_max.
TEST(TranscriptionGuess, TheSegwaysLookupsCapTheSpeedsOnASlope) {
  const double slope = 12.0 * kDegree;
  const terrain::ElevationMap map = rampMap(slope);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  const BoundaryValueProblem problem = segwayUpTheRamp(lookups);
  const std::vector<Eigen::Vector2d> path = {{4.0, 5.0}, {34.0, 5.0}};

  const Expected<TranscriptionGuess> blind = guessFromPath(path, problem, 0.25);
  const Expected<TranscriptionGuess> capped = guessFromPath(path, problem, 0.25, &vehicle);
  ASSERT_TRUE(blind.ok() && capped.ok());
  const double v_cap = lookups.bounds.speedLimit(slope);
  const double a_cap = lookups.bounds.accelerationLimit(slope);
  ASSERT_LT(v_cap, 0.7 * problem.limits.v_max);  // the look-ups bind on this ramp
  EXPECT_GT(largestSpeed(*blind), v_cap);
  EXPECT_LE(largestSpeed(*capped), 0.8 * v_cap + 0.01);
  EXPECT_GE(largestSpeed(*capped), 0.75 * v_cap);  // and it does drive at the cap
  for (std::size_t i = 1; i < capped->points.size(); ++i) {
    const double dv = capped->points[i](3) - capped->points[i - 1](3);
    const double dt = capped->t[i] - capped->t[i - 1];
    ASSERT_GT(dt, 0.0);
    EXPECT_LE(std::abs(dv) / dt, 0.8 * a_cap + 0.01) << "sample " << i;
  }
  EXPECT_GT(capped->finalTime(), blind->finalTime());
}

// Beyond the Segway's drivable slope its look-ups allow nothing: the guess still crosses at a
// tenth of v_max (the optimiser has to leave such a path; a guess at rest there would give it no
// direction), with finite, increasing times.
TEST(TranscriptionGuess, OnAnUndrivableSlopeTheGuessKeepsATenthOfTheLimits) {
  const terrain::ElevationMap map = rampMap(24.0 * kDegree);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  const BoundaryValueProblem problem = segwayUpTheRamp(lookups);
  ASSERT_EQ(lookups.bounds.speedLimit(24.0 * kDegree), 0.0);
  const Expected<TranscriptionGuess> guess =
      guessFromPath({{4.0, 5.0}, {34.0, 5.0}}, problem, 0.25, &vehicle);
  ASSERT_TRUE(guess.ok()) << guess.reason();
  EXPECT_NEAR(largestSpeed(*guess), 0.1 * problem.limits.v_max, 1e-9);
  EXPECT_TRUE(std::isfinite(guess->finalTime()));
  for (std::size_t i = 1; i < guess->t.size(); ++i) EXPECT_GT(guess->t[i], guess->t[i - 1]);
}

// Without speed tables the vehicle changes nothing.
TEST(TranscriptionGuess, WithoutTablesTheVehicleChangesNothing) {
  const terrain::ElevationMap map = rampMap(12.0 * kDegree);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  BoundaryValueProblem problem = segwayUpTheRamp(lookups);
  problem.tables.segway = nullptr;
  const std::vector<Eigen::Vector2d> path = {{4.0, 5.0}, {20.0, 8.0}, {34.0, 5.0}};
  const Expected<TranscriptionGuess> blind = guessFromPath(path, problem, 0.25);
  const Expected<TranscriptionGuess> given = guessFromPath(path, problem, 0.25, &vehicle);
  ASSERT_TRUE(blind.ok() && given.ok());
  ASSERT_EQ(blind->t, given->t);
  for (std::size_t i = 0; i < blind->points.size(); ++i) {
    EXPECT_TRUE((blind->points[i] - given->points[i]).isZero(0.0));
  }
}

// A guess read at its own two points sees flat ground; read at a fine mesh's points it crosses a
// ridge steeper than pitch_max and the Segway's drivable slope between them (as a coarse mesh's
// solution can): guessLimitExcess says by how much. Within every limit, it is 0.
TEST(TranscriptionGuess, TheLimitExcessSeesGroundBetweenThePoints) {
  terrain::ElevationMap map = terrain::testing::planeMap(40, 160, 0.25, 0.0, 0.0, 0.0);
  terrain::testing::raiseRidge(map, 19.0, 1.0, 0.5, 100.0, 1.0);  // flanks near 50 deg
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  const BoundaryValueProblem problem = segwayUpTheRamp(lookups);
  TranscriptionGuess straight;
  straight.t = {0.0, 30.0};
  straight.points.assign(2, PointVector::Zero());
  straight.points[0] << 4.0, 5.0, 0.0, 1.0, 0.0, 0.0, 0.0;
  straight.points[1] << 34.0, 5.0, 0.0, 1.0, 0.0, 0.0, 0.0;

  EXPECT_LE(guessLimitExcess(straight, problem, vehicle, 2), 0.0);
  const double excess = guessLimitExcess(straight, problem, vehicle, 241);
  EXPECT_GT(excess, 0.4);  // |pitch| about 1.5 x pitch_max on the flanks
  EXPECT_LT(excess, 1.0);

  // On the flat map alone, at 1 m/s: every limit holds at every point.
  const terrain::ElevationMap flat = terrain::testing::planeMap(40, 160, 0.25, 0.0, 0.0, 0.0);
  const terrain::TerrainSurface flat_surface(flat, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel flat_vehicle(flat_surface);
  EXPECT_LE(guessLimitExcess(straight, problem, flat_vehicle, 241), 0.0);
}

}  // namespace
}  // namespace terratraj::ocp
