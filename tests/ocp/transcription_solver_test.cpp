// solveTranscription's rounds: a limit the ground sets, broken between the points of a coarse
// mesh, is met by halving the intervals where it breaks, not every interval.
#include "terratraj/ocp/transcription_solver.hpp"

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

// Level ground, 40 m x 10 m at 0.25 m, with one step up a 17 deg slope from x = 20 to 21 m:
// there the Segway's look-ups allow 1 m/s, elsewhere 3.5.
terrain::ElevationMap groundWithAStep() {
  terrain::ElevationMap map = terrain::testing::planeMap(40, 160, 0.25, 0.0, 0.0, 0.0);
  const terrain::GridGeometry& g = map.geometry();
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const double x = g.cellCenter({r, c}).x();
      map.elevation()(r, c) =
          static_cast<float>(std::tan(17.0 * kDegree) * std::clamp(x - 20.0, 0.0, 1.0));
    }
  }
  return map;
}

TEST(TranscriptionSolver, ACoarseMeshIsRefinedWhereTheGroundBreaksALimit) {
  const terrain::ElevationMap map = groundWithAStep();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  const BoundaryValueProblem problem = testing::segwayAlongX(lookups, 36.0, 25.0 * kDegree);
  const Expected<TranscriptionGuess> guess =
      guessFromPath({{4.0, 5.0}, {36.0, 5.0}}, problem, 0.25);  // blind to the step
  ASSERT_TRUE(guess.ok()) << guess.reason();

  TranscriptionSolveOptions options;
  options.transcription.intervals = 20;
  options.max_rounds = 6;
  options.transcription.linear_controls = true;
  options.map = &map;
  const VerifiedTranscription result = solveTranscription(vehicle, problem, *guess, options);

  ASSERT_EQ(result.status, SolveStatus::kConverged) << result.reason;
  ASSERT_GE(result.rounds.size(), 2u);
  // Some round refined only part of its mesh, and the mesh solved last is not uniform.
  bool local = false;
  for (std::size_t r = 1; r < result.rounds.size(); ++r) {
    local = local || (result.rounds[r].intervals > result.rounds[r - 1].intervals &&
                      result.rounds[r].intervals < 2 * result.rounds[r - 1].intervals);
  }
  EXPECT_TRUE(local);
  const std::vector<double>& mesh = result.solution.mesh;
  double shortest = 1.0, longest = 0.0;
  for (std::size_t k = 0; k + 1 < mesh.size(); ++k) {
    shortest = std::min(shortest, mesh[k + 1] - mesh[k]);
    longest = std::max(longest, mesh[k + 1] - mesh[k]);
  }
  EXPECT_GT(longest, 1.5 * shortest);
  EXPECT_TRUE(result.verdict.check.ok()) << result.verdict.check.summary();
}

}  // namespace
}  // namespace terratraj::ocp
