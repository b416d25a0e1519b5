// Local mesh refinement: where a re-simulated trajectory breaks the ground's limits, by
// interval, and the mesh with those intervals halved.
#include "terratraj/ocp/mesh_split.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../terrain/test_maps.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::ocp {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Samples every 0.1 s over 10 s at 0.5 m/s on level ground, heading 0.
models::Trajectory levelDrive() {
  models::Trajectory trajectory;
  for (int i = 0; i <= 100; ++i) {
    models::TrajectorySample s = models::TrajectorySample::unknown();
    s.t = 0.1 * i;
    s.x = 0.05 * i;
    s.y = s.z = s.heading = s.roll = s.pitch = s.omega = s.curvature = 0.0;
    s.v = 0.5;
    trajectory.samples.push_back(s);
  }
  return trajectory;
}

BoundaryValueProblem limitsOnly() {
  BoundaryValueProblem problem;
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  problem.limits.pitch_max = 20.0 * kDegree;
  problem.limits.roll_max = 20.0 * kDegree;
  return problem;
}

// Each break lands in the interval of its samples, by its relative excess: pitch 1.2 x pitch_max
// in the fourth interval, roll 1.1 x roll_max in the first, a speed step of 0.1 m/s in 0.1 s
// (1 m/s^2, twice a_max) in the fifth; the second and third hold every limit.
TEST(MeshSplit, TheExcessFallsInTheIntervalsWhereTheRowsBreakALimit) {
  const BoundaryValueProblem problem = limitsOnly();
  models::Trajectory trajectory = levelDrive();
  for (int i = 62; i <= 66; ++i) trajectory.samples[i].pitch = 1.2 * problem.limits.pitch_max;
  trajectory.samples[10].roll = -1.1 * problem.limits.roll_max;
  for (int i = 85; i <= 100; ++i) trajectory.samples[i].v = 0.6;
  const std::vector<double> nodes = {0.0, 2.0, 4.0, 6.0, 8.0, 10.0};

  const std::vector<double> excess = intervalLimitExcess(trajectory, nodes, problem);
  ASSERT_EQ(excess.size(), 5u);
  EXPECT_NEAR(excess[0], 0.1, 1e-9);
  EXPECT_EQ(excess[1], 0.0);
  EXPECT_EQ(excess[2], 0.0);
  EXPECT_NEAR(excess[3], 0.2, 1e-9);
  EXPECT_NEAR(excess[4], (1.0 - 0.5) / 0.5, 1e-9);
}

// The Segway's look-ups bound the speed by slope: 0.9 m/s on a 19 deg slope breaks its bound
// there (relative to v_max), and nowhere on level ground.
TEST(MeshSplit, TheSegwaysSlopeBoundCountsAtTheRowsAttitude) {
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  BoundaryValueProblem problem = limitsOnly();
  problem.limits.pitch_max = 25.0 * kDegree;
  problem.tables.segway = &lookups;
  models::Trajectory trajectory = levelDrive();
  for (models::TrajectorySample& s : trajectory.samples) s.v = 0.9;
  const double slope = 19.0 * kDegree;
  for (int i = 30; i <= 32; ++i) trajectory.samples[i].pitch = slope;
  const double cap = lookups.bounds.speedLimit(slope);
  ASSERT_LT(cap, 0.9);

  const std::vector<double> excess =
      intervalLimitExcess(trajectory, {0.0, 2.5, 5.0, 10.0}, problem);
  ASSERT_EQ(excess.size(), 3u);
  EXPECT_EQ(excess[0], 0.0);
  EXPECT_NEAR(excess[1], (0.9 - cap) / problem.limits.v_max, 1e-9);
  EXPECT_EQ(excess[2], 0.0);
}

TEST(MeshSplit, HalvesTheMarkedIntervalsUpToTheCap) {
  const std::vector<double> mesh = {0.0, 0.25, 0.5, 0.75, 1.0};
  const std::vector<double> split = splitIntervals(mesh, {false, true, false, true}, 100);
  EXPECT_EQ(split, (std::vector<double>{0.0, 0.25, 0.375, 0.5, 0.75, 0.875, 1.0}));
  // At most max_intervals: the first marked interval only.
  const std::vector<double> capped = splitIntervals(mesh, {false, true, false, true}, 5);
  EXPECT_EQ(capped, (std::vector<double>{0.0, 0.25, 0.375, 0.5, 0.75, 1.0}));
  EXPECT_EQ(splitIntervals(mesh, {false, false, false, false}, 100), mesh);
}

// A mesh given to the transcription is checked (intervals + 1 node times from 0 to 1,
// increasing) and solved on as given.
TEST(MeshSplit, AGivenMeshIsCheckedThenSolvedOn) {
  DirectTranscriptionOptions options;
  options.intervals = 4;
  options.mesh = {0.0, 0.5, 1.0};
  EXPECT_NE(validateTranscriptionOptions(options), std::nullopt);
  options.mesh = {0.0, 0.25, 0.2, 0.5, 1.0};
  EXPECT_NE(validateTranscriptionOptions(options), std::nullopt);
  options.mesh = {0.1, 0.25, 0.3, 0.5, 1.0};
  EXPECT_NE(validateTranscriptionOptions(options), std::nullopt);

  const terrain::ElevationMap map = terrain::testing::planeMap(40, 80, 0.25, 0.0, 0.0, 0.0);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = limitsOnly();
  problem.start = {4.0, 5.0, 0.0, 0.0, 0.0};
  problem.goal = {8.0, 5.0, 0.0, 0.0, 0.0};
  const Expected<TranscriptionGuess> guess = guessFromPath({{4.0, 5.0}, {8.0, 5.0}}, problem);
  ASSERT_TRUE(guess.ok()) << guess.reason();
  options.intervals = 12;
  options.mesh =
      splitIntervals(uniformMesh(8), {false, false, true, true, true, true, false, false}, 100);
  ASSERT_EQ(options.mesh.size(), 13u);
  ASSERT_EQ(validateTranscriptionOptions(options), std::nullopt);
  const TranscriptionSolution solution =
      solveDirectTranscription(vehicle, problem, *guess, options);
  ASSERT_EQ(solution.result.status, SolveStatus::kConverged) << solution.result.reason;
  EXPECT_EQ(solution.mesh, options.mesh);
}

}  // namespace
}  // namespace terratraj::ocp
