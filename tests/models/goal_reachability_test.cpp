#include "terratraj/models/goal_reachability.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "terratraj/models/four_wheel_attitude_model.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::models {
namespace {

constexpr double kPi = 3.14159265358979323846;

VehicleLimits limits25() {
  VehicleLimits limits;
  limits.pitch_max = limits.roll_max = 25.0 * kPi / 180.0;
  return limits;
}

// A 30 m square map of 0.25 m cells with heights z(x, y).
terrain::ElevationMap mapOf(const std::function<double(double, double)>& z) {
  terrain::GridGeometry g;
  g.rows = g.cols = 120;
  g.cell = 0.25;
  terrain::ElevationMap map(g);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      map.elevation()(r, c) = static_cast<float>(z(p.x(), p.y()));
    }
  }
  return map;
}

// A crater around (15, 15): a flat floor of radius 4 m, a wall rising at `wall_deg` over 2 m,
// a flat plain beyond; `gap_deg` > 0 cuts a notch of that opening through the wall at bearing 0
// (towards +x), a ramp from the floor to the plain's height over 5 m (at most 22 deg uphill).
terrain::ElevationMap crater(double wall_deg, double gap_deg) {
  const double rim = 2.0 * std::tan(wall_deg * kPi / 180.0);
  return mapOf([=](double x, double y) {
    const double r = std::hypot(x - 15.0, y - 15.0);
    const double bearing = std::atan2(y - 15.0, x - 15.0);
    if (gap_deg > 0.0 && std::abs(bearing) < 0.5 * gap_deg * kPi / 180.0) {
      return rim * std::clamp((r - 4.0) / 5.0, 0.0, 1.0);
    }
    return rim * std::clamp((r - 4.0) / 2.0, 0.0, 1.0);
  });
}

GoalReachability check(const terrain::ElevationMap& map, const PlanarPose& start,
                       const PlanarPose& goal, bool four_wheel = false) {
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  if (four_wheel) {
    const FourWheelAttitudeModel vehicle(surface, FourWheelGeometry{});
    return checkGoalReachability(vehicle, map, limits25(), start, goal);
  }
  const PointAttitudeModel vehicle(surface);
  return checkGoalReachability(vehicle, map, limits25(), start, goal);
}

TEST(GoalReachability, AGoalOutsideASteepCraterIsUnreachableAndSaysWhy) {
  const terrain::ElevationMap map = crater(45.0, 0.0);
  for (const bool four_wheel : {false, true}) {
    const GoalReachability r = check(map, {15.0, 15.0, 0.0}, {23.0, 15.0, 0.0}, four_wheel);
    EXPECT_FALSE(r.reachable) << "four_wheel " << four_wheel;
    EXPECT_NE(
        r.reason.find("slopes where no heading the vehicle can turn to keeps pitch within 25 deg"),
        std::string::npos)
        << r.reason;
    // The floor and the wall's foot: about pi 4^2 = 50 m^2 (800 cells), not the whole map.
    EXPECT_GT(r.cells_reached, 500u);
    EXPECT_LT(r.cells_reached, 1400u);
  }
  // Inside the crater: reachable.
  EXPECT_TRUE(check(map, {15.0, 15.0, 0.0}, {12.0, 16.0, kPi}).reachable);
}

TEST(GoalReachability, ANotchThroughTheWallOrAGentleWallMakesItReachable) {
  for (const bool four_wheel : {false, true}) {
    EXPECT_TRUE(
        check(crater(45.0, 30.0), {15.0, 15.0, kPi}, {15.0, 26.0, 0.5 * kPi}, four_wheel).reachable)
        << "through the notch, four_wheel " << four_wheel;
    // 30 deg is above both limits, but driving across it at 45 deg keeps pitch and roll near
    // atan(tan 30 / sqrt 2) = 22 deg.
    EXPECT_TRUE(
        check(crater(30.0, 0.0), {15.0, 15.0, 0.0}, {23.0, 15.0, 0.0}, four_wheel).reachable)
        << "across a 30 deg wall, four_wheel " << four_wheel;
  }
}

TEST(GoalReachability, ALethalRingBoxesTheGoalIn) {
  terrain::ElevationMap map = mapOf([](double, double) { return 0.0; });
  terrain::GridLayer& lethal = map.addLayer(terrain::layer_names::kLethal, 0.0f);
  const terrain::CellIndex goal = *map.geometry().cellAt({20.0, 20.0});
  for (int dr = -6; dr <= 6; ++dr) {
    for (int dc = -6; dc <= 6; ++dc) {
      if (std::max(std::abs(dr), std::abs(dc)) == 6) lethal(goal.row + dr, goal.col + dc) = 1;
    }
  }
  const GoalReachability r = check(map, {3.0, 3.0, 0.0}, {20.0, 20.0, 0.0});
  EXPECT_FALSE(r.reachable);
  EXPECT_NE(r.reason.find("lethal cells"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("the map's edge"), std::string::npos) << r.reason;
  // Settled by the search by cell: one state per cell, not one per (cell, sector).
  EXPECT_EQ(r.states_visited, r.cells_reached);
  // From inside the ring to inside it: reachable, and the walk is short.
  const GoalReachability inside = check(map, {19.0, 19.0, 0.25 * kPi}, {20.0, 20.0, 0.25 * kPi});
  EXPECT_TRUE(inside.reachable);
  EXPECT_LT(inside.cells_reached, 20u);
}

TEST(GoalReachability, OverOpenGroundItWalksNearlyStraightToTheGoal) {
  const terrain::ElevationMap map = mapOf([](double x, double y) { return 0.1 * x + 0.05 * y; });
  const GoalReachability r = check(map, {2.0, 2.0, 0.0}, {18.0, 12.0, 0.0});
  EXPECT_TRUE(r.reachable);
  EXPECT_TRUE(r.reason.empty());
  // 64 cells along x, 40 along y: a walk of 64 steps.
  EXPECT_LT(r.cells_reached, 100u);
}

}  // namespace
}  // namespace terratraj::models
