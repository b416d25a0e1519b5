#include "terratraj/models/curvature_trap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "terrain/test_maps.hpp"
#include "terratraj/models/goal_reachability.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/terrain/raster_io.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::models {
namespace {

constexpr double kPi = 3.14159265358979323846;

VehicleLimits limits25() {
  VehicleLimits limits;
  limits.kappa_max = 1.0;  // turning radius 1 m on flat ground
  limits.pitch_max = limits.roll_max = 25.0 * kPi / 180.0;
  return limits;
}

// A flat 30 m square of 0.25 m cells; `corridor_width_m` > 0 adds a dead-end corridor along x at
// y = 15, closed at x = 12, its walls one cell of lethal ground each.
terrain::ElevationMap flatMap(double corridor_width_m = 0.0) {
  terrain::GridGeometry g;
  g.rows = g.cols = 120;
  g.cell = 0.25;
  terrain::ElevationMap map(g);
  if (corridor_width_m <= 0.0) return map;
  terrain::GridLayer& lethal = map.addLayer(terrain::layer_names::kLethal, 0.0f);
  const double half = 0.5 * corridor_width_m;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      const double off = std::abs(p.y() - 15.0);
      const bool side = p.x() < 12.25 && off > half && off < half + 0.25;
      const bool end = p.x() > 12.0 && p.x() < 12.25 && off < half + 0.25;
      if (side || end) lethal(r, c) = 1.0f;
    }
  }
  return map;
}

// The real DEM of the robustness set's pocket (docs/benchmarks.md): davosdorf at rover scale.
terrain::ElevationMap davosdorf() {
  terrain::RasterLoadOptions load;
  load.cell = 0.25;
  load.z_scale = 0.0125;
  return terrain::loadElevationMap(terrain::testing::sharedData("davosdorf.tif"), load);
}

TEST(CurvatureTrap, OpenGroundEscapesAtOnceBothWays) {
  const terrain::ElevationMap map = flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const PointAttitudeModel vehicle(surface);
  for (const TrapDirection direction : {TrapDirection::kLeaving, TrapDirection::kArriving}) {
    const CurvatureTrap t =
        checkCurvatureTrap(vehicle, map, limits25(), {15.0, 15.0, 0.3}, direction, std::nullopt);
    EXPECT_EQ(t.outcome, TrapOutcome::kEscapes);
    // Nearest exit first: a walk of about window / step moves to the edge, and its fan.
    EXPECT_LT(t.boxes_settled, 1000u);
  }
}

TEST(CurvatureTrap, ADeadEndNarrowerThanTheTurningCircleTrapsAVehicleDrivingIn) {
  // 1 m wide, turning radius 1 m: a vehicle heading for the end cannot turn back.
  const terrain::ElevationMap map = flatMap(1.0);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const PointAttitudeModel vehicle(surface);
  const PlanarPose start{10.5, 15.0, 0.0}, behind{8.0, 15.0, kPi};
  // Boxes of 2 cm (the first default level): the corridor's 1.75 m are about 10^5 boxes.
  const CurvatureTrapOptions coarse = defaultCurvatureLevels().front();
  const CurvatureTrap t =
      checkCurvatureTrap(vehicle, map, limits25(), start, TrapDirection::kLeaving, behind, coarse);
  EXPECT_EQ(t.outcome, TrapOutcome::kTrapped);
  EXPECT_LT(t.radius_m, 1.8);  // the corridor's last 1.75 m
  // checkGoalReachability's search by sector turns in place and lets it out; the curvature check
  // does not, and says so.
  const GoalReachability r = checkGoalReachability(vehicle, map, limits25(), start, behind);
  EXPECT_FALSE(r.reachable);
  ASSERT_TRUE(r.start_trap.has_value());
  EXPECT_EQ(r.start_trap->outcome, TrapOutcome::kTrapped);
  EXPECT_EQ(r.start_trap->level, 0);
  EXPECT_NE(r.reason.find("curvature at most 1 1/m"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("leave the start's pose"), std::string::npos) << r.reason;
  // Without the curvature check the relaxation cannot tell.
  GoalReachabilityOptions no_curvature;
  no_curvature.curvature.clear();
  EXPECT_TRUE(
      checkGoalReachability(vehicle, map, limits25(), start, behind, no_curvature).reachable);
  // Heading out of the corridor, or with a turning radius the corridor holds: reachable.
  EXPECT_TRUE(checkGoalReachability(vehicle, map, limits25(), {10.5, 15.0, kPi}, behind).reachable);
  VehicleLimits tight = limits25();
  tight.kappa_max = 4.0;  // radius 0.25 m
  EXPECT_TRUE(checkGoalReachability(vehicle, map, tight, start, behind).reachable);
}

TEST(CurvatureTrap, ADeadEndWiderThanTheTurningCircleLetsTheVehicleTurnBack) {
  const terrain::ElevationMap map = flatMap(3.0);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const PointAttitudeModel vehicle(surface);
  const CurvatureTrap t = checkCurvatureTrap(vehicle, map, limits25(), {10.5, 15.0, 0.0},
                                             TrapDirection::kLeaving, std::nullopt);
  EXPECT_EQ(t.outcome, TrapOutcome::kEscapes);
}

TEST(CurvatureTrap, TheOtherEndInsideTheRegionIsNoProof) {
  const terrain::ElevationMap map = flatMap(1.0);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const PointAttitudeModel vehicle(surface);
  const CurvatureTrap t =
      checkCurvatureTrap(vehicle, map, limits25(), {10.5, 15.0, 0.0}, TrapDirection::kLeaving,
                         PlanarPose{11.5, 15.0, 0.0}, defaultCurvatureLevels().front());
  EXPECT_EQ(t.outcome, TrapOutcome::kReachesOther);
  // Backwards from the far pose: paths arriving there are followed back, out of the corridor
  // (followed forwards, they would be trapped at its end).
  const CurvatureTrap back =
      checkCurvatureTrap(vehicle, map, limits25(), {11.5, 15.0, 0.0}, TrapDirection::kArriving,
                         PlanarPose{10.5, 15.0, 0.0}, defaultCurvatureLevels().front());
  EXPECT_NE(back.outcome, TrapOutcome::kTrapped);
}

TEST(CurvatureTrap, TheDavosdorfPocketIsProvedForThePointModel) {
  // The robustness set's seed-7 davosdorf problem 2: the goal stands on a 20 deg side slope
  // between ridges; every way into its pose rolls or pitches beyond 25 deg within half a metre.
  const terrain::ElevationMap map = davosdorf();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const PointAttitudeModel vehicle(surface);
  const PlanarPose start{28.926, 62.949, -2.3773}, goal{18.546, 57.531, -1.8041};
  const GoalReachability r = checkGoalReachability(vehicle, map, limits25(), start, goal);
  EXPECT_FALSE(r.reachable);
  ASSERT_TRUE(r.goal_trap.has_value());
  EXPECT_EQ(r.goal_trap->outcome, TrapOutcome::kTrapped);
  EXPECT_LT(r.goal_trap->radius_m, 1.0);
  EXPECT_NE(r.reason.find("arrive at the goal's pose"), std::string::npos) << r.reason;
}

// Soundness: on the roughest ground of a real DEM, every curvature-bounded path that keeps the
// limits (drawn at random, checked every centimetre) joins two poses the check cannot separate:
// from its start, leaving, the search never proves the end unreachable, nor from its end,
// arriving, the start.
TEST(CurvatureTrap, NoDrivenPathIsEverDeclaredTrapped) {
  const terrain::ElevationMap map = davosdorf();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  for (const VehicleModelKind kind : {VehicleModelKind::kPoint, VehicleModelKind::kFourWheel}) {
    const std::unique_ptr<TerrainFollowingModel> vehicle = makeTerrainFollowingModel(kind, surface);
    const VehicleLimits limits = limits25();
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    AttitudeWorkspace workspace;
    AttitudeResult attitude;
    const auto within = [&](const PlanarPose& p) {
      workspace.has_warm_start = false;
      return vehicle->compute(p, workspace, attitude) == AttitudeStatus::kOk &&
             std::abs(attitude.attitude.pitch) <= limits.pitch_max &&
             std::abs(attitude.attitude.roll) <= limits.roll_max;
    };
    int paths = 0;
    for (int draw = 0; draw < 4000 && paths < 12; ++draw) {
      // Around the pocket (the ridge west of the map's centre), 1 to 2 m long.
      PlanarPose p{16.0 + 14.0 * unit(random), 54.0 + 10.0 * unit(random),
                   2.0 * kPi * unit(random)};
      if (!within(p)) continue;
      const PlanarPose begin = p;
      const double length = 1.0 + unit(random);
      double kappa = 0.0;
      bool kept = true;
      for (double s = 0.0; s < length && kept; s += 0.01) {
        if (std::fmod(s, 0.1) < 0.01) kappa = (2.0 * unit(random) - 1.0) * limits.kappa_max;
        p.x += 0.01 * std::cos(p.heading);
        p.y += 0.01 * std::sin(p.heading);
        p.heading += 0.01 * kappa;
        kept = within(p);
      }
      if (!kept) continue;
      ++paths;
      const CurvatureTrap leaving =
          checkCurvatureTrap(*vehicle, map, limits, begin, TrapDirection::kLeaving, p);
      const CurvatureTrap arriving =
          checkCurvatureTrap(*vehicle, map, limits, p, TrapDirection::kArriving, begin);
      EXPECT_NE(leaving.outcome, TrapOutcome::kTrapped) << begin.x << " " << begin.y;
      EXPECT_NE(arriving.outcome, TrapOutcome::kTrapped) << p.x << " " << p.y;
    }
    EXPECT_EQ(paths, 12) << "too few admissible paths drawn";
  }
}

}  // namespace
}  // namespace terratraj::models
