#include "terratraj/models/segway_rmp_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/trajectory_checker.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::models {
namespace {

using terrain::ElevationMap;
using terrain::Interpolation;
using terrain::TerrainSurface;

const std::string kDataDir = std::string(TERRATRAJ_SOURCE_DIR) + "/models/data/segway_rmp/";

ElevationMap ramp(double slope) {
  terrain::GridGeometry g;
  g.rows = g.cols = 80;
  g.cell = 0.25;
  ElevationMap map(g);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c)
      map.elevation()(r, c) = static_cast<float>(std::tan(slope) * (c + 0.5) * g.cell);
  }
  return map;
}

TEST(SegwayLookups, ShippedFilesMatchTheBuiltInDefaults) {
  const SegwayLookups files =
      readSegwayLookups(kDataDir + "pitch_response.json", kDataDir + "slope_bounds.json");
  const SegwayLookups defaults = defaultSegwayLookups();
  for (double a = -2.5; a <= 2.5; a += 0.3) {
    for (double s = -0.4; s <= 0.4; s += 0.07) {
      EXPECT_NEAR(files.pitch_response.pitch(a, s), defaults.pitch_response.pitch(a, s), 2e-6);
    }
  }
  // The files round to 6 decimals; interpolating between rounded grid points adds a little.
  for (double s = -0.5; s <= 0.5; s += 0.01) {
    EXPECT_NEAR(files.bounds.speedLimit(s), defaults.bounds.speedLimit(s), 1e-5);
    EXPECT_NEAR(files.bounds.accelerationLimit(s), defaults.bounds.accelerationLimit(s), 1e-5);
  }
}

TEST(SegwayLookups, PaperFiguresAndPhysicalSigns) {
  const SegwayLookups lookups = defaultSegwayLookups();
  EXPECT_DOUBLE_EQ(lookups.bounds.speedLimit(0.0), 3.5);
  EXPECT_DOUBLE_EQ(lookups.bounds.accelerationLimit(0.0), 2.0);
  EXPECT_NEAR(lookups.bounds.speedLimit(17.0 * M_PI / 180.0), 1.0, 1e-9);
  EXPECT_EQ(lookups.bounds.speedLimit(20.0 * M_PI / 180.0), 0.0);
  // Leaning forward (nose down, pitch < 0) to accelerate; at rest on the level, upright.
  EXPECT_LT(lookups.pitch_response.pitch(1.0, 0.0), 0.0);
  EXPECT_GT(lookups.pitch_response.pitch(-1.0, 0.0), 0.0);
  EXPECT_NEAR(lookups.pitch_response.pitch(0.0, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(lookups.pitch_response.pitch(1.0, 0.0), -std::atan(1.0 / 9.81), 1e-3);
}

TEST(SegwayLookups, BadFilesAreInputErrors) {
  const std::string bad =
      (std::filesystem::temp_directory_path() / "terratraj_segway_bad.json").string();
  std::ofstream(bad)
      << R"({"kind": "segway_slope_bounds", "slope_rad": [0, -1], "v_max": [1, 1], "a_max": [1, 1]})";
  try {
    readSegwayLookups(kDataDir + "pitch_response.json", bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("increase strictly"));
  }
  EXPECT_THROW(readSegwayLookups(bad, kDataDir + "slope_bounds.json"), InputError);  // wrong kind
  EXPECT_THROW(readSegwayLookups("/nonexistent.json", kDataDir + "slope_bounds.json"), InputError);
}

TEST(SegwayRmpModel, MovesAlongArcsOnFlatGround) {
  const ElevationMap map = ramp(0.0);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const SegwayRmpModel model(surface);
  SegwayState state{5.0, 5.0, 0.3, 1.0, 0.5};
  SegwayState end;
  ASSERT_TRUE(model.propagate(state, Eigen::Vector2d::Zero(), 0.2, end));
  const double r = 1.0 / 0.5;
  EXPECT_NEAR(end.x, 5.0 + r * (std::sin(0.3 + 0.1) - std::sin(0.3)), 1e-7);
  EXPECT_NEAR(end.y, 5.0 - r * (std::cos(0.3 + 0.1) - std::cos(0.3)), 1e-7);
  EXPECT_NEAR(end.heading, 0.4, 1e-7);
  ASSERT_TRUE(model.propagate(state, Eigen::Vector2d(1.0, 0.0), 0.2, end));
  EXPECT_NEAR(end.v, 1.2, 1e-12);
}

TEST(SegwayLookups, DrivableSlopeIsWhereTheBoundsEnd) {
  EXPECT_NEAR(defaultSegwayLookups().bounds.drivableSlope(), 20.0 * M_PI / 180.0, 1e-12);
  const SegwaySlopeBounds level_only({-0.1, 0.0, 0.1}, {0.0, 1.0, 0.0}, {0.0, 1.0, 0.0});
  EXPECT_DOUBLE_EQ(level_only.drivableSlope(), 0.1);
  const SegwaySlopeBounds everywhere({-0.1, 0.1}, {1.0, 1.0}, {1.0, 1.0});
  EXPECT_TRUE(std::isinf(everywhere.drivableSlope()));
}

// The optimisers' bounds: the look-ups on drivable slopes (below them at their rounded corners,
// whichever way they bend; equal away from the corners), C1,
// continued below 0 beyond the edge (the last piece's descent, continuous there), on each side by
// its own edge.
TEST(SegwayLookups, TheOptimisersBoundsPointBackToDrivableGround) {
  const SegwaySlopeBounds& bounds = defaultSegwayLookups().bounds;
  const double deg = M_PI / 180.0;
  for (double d = -19.95; d <= 19.95; d += 0.05) {
    const double s = d * deg;
    EXPECT_LE(bounds.optimiserSpeedLimit(s), bounds.speedLimit(s) + 1e-12) << d;
    // a_max = 2 - g sin|slope| / 2 between grid points bends up slightly at 10 deg: still below.
    EXPECT_LE(bounds.optimiserAccelerationLimit(s), bounds.accelerationLimit(s) + 1e-12) << d;
    const bool near_a_corner = std::abs(std::abs(d) - 5.0) < 0.5 ||
                               std::abs(std::abs(d) - 10.0) < 0.5 ||
                               std::abs(std::abs(d) - 17.0) < 0.5 || std::abs(d) < 0.5;
    if (!near_a_corner) {
      EXPECT_NEAR(bounds.optimiserSpeedLimit(s), bounds.speedLimit(s), 1e-9) << d;
      EXPECT_NEAR(bounds.optimiserAccelerationLimit(s), bounds.accelerationLimit(s), 1e-9) << d;
    }
    // C1: the one-sided slopes agree everywhere.
    const double h = 1e-7;
    const auto slope_of = [&](double a, double b) {
      return (bounds.optimiserSpeedLimit(b) - bounds.optimiserSpeedLimit(a)) / (b - a);
    };
    EXPECT_NEAR(slope_of(s - h, s), slope_of(s, s + h), 1e-3) << d;
  }
  // 1 m/s over the 3 deg from 17 to 20 deg, continued.
  EXPECT_NEAR(bounds.optimiserSpeedLimit(23.0 * deg), -1.0, 1e-6);
  EXPECT_NEAR(bounds.optimiserSpeedLimit(-23.0 * deg), -1.0, 1e-6);
  EXPECT_NEAR(bounds.optimiserSpeedLimit(20.0 * deg + 1e-9), 0.0, 1e-6);
  EXPECT_LT(bounds.optimiserAccelerationLimit(21.0 * deg), 0.0);
  EXPECT_GT(bounds.optimiserAccelerationLimit(21.0 * deg),
            bounds.optimiserAccelerationLimit(22.0 * deg));
  // Asymmetric: drivable to 0.1 rad uphill, 0.2 rad downhill.
  const SegwaySlopeBounds tilted({-0.2, 0.0, 0.1}, {0.0, 1.0, 0.0}, {0.0, 1.0, 0.0});
  EXPECT_NEAR(tilted.optimiserSpeedLimit(-0.15), 0.25, 1e-12);
  EXPECT_NEAR(tilted.optimiserSpeedLimit(-0.3), -0.5, 1e-6);
  EXPECT_NEAR(tilted.optimiserSpeedLimit(0.15), -0.5, 1e-6);
  // A corner that bends up sharply (slope -1 then +3 per rad at 0): below the look-up across
  // it, C1, equal to it from 0.5 deg away.
  const SegwaySlopeBounds valley({-0.2, 0.0, 0.2}, {1.2, 1.0, 1.6}, {1.0, 1.0, 1.0});
  for (double d = -0.995; d <= 1.0; d += 0.01) {  // off the rounding's ends (C1, not C2)
    const double s = d * deg;
    EXPECT_LE(valley.optimiserSpeedLimit(s), valley.speedLimit(s) + 1e-12) << d;
    if (std::abs(d) >= 0.5) {
      EXPECT_NEAR(valley.optimiserSpeedLimit(s), valley.speedLimit(s), 1e-12) << d;
    }
    double ds = 0.0;
    valley.optimiserSpeedLimit(s, &ds);
    const double h = 1e-7;
    EXPECT_NEAR(
        ds, (valley.optimiserSpeedLimit(s + h) - valley.optimiserSpeedLimit(s - h)) / (2 * h), 1e-6)
        << d;
  }
  EXPECT_LT(valley.optimiserSpeedLimit(0.0), 1.0);
  // Drivable everywhere: the ends of the grid hold beyond it.
  const SegwaySlopeBounds everywhere({-0.1, 0.1}, {1.0, 2.0}, {1.0, 1.0});
  EXPECT_NEAR(everywhere.optimiserSpeedLimit(0.5), 2.0, 1e-12);
  EXPECT_NEAR(everywhere.optimiserSpeedLimit(-0.5), 1.0, 1e-12);
}

// The optimisers' versions of the look-ups against their finite-difference twins, and the C1
// platform pitch through the grid's values, close to the bilinear look-up between them.
TEST(SegwayLookups, TheOptimisersVersionsHaveTheirDerivatives) {
  const SegwayLookups lookups = defaultSegwayLookups();
  const double deg = M_PI / 180.0, h = 1e-6;
  double worst_departure = 0.0;
  for (double a = -2.4; a <= 2.4; a += 0.0625) {
    for (double d = -24.0; d <= 24.0; d += 0.37) {
      const double s = d * deg;
      double d_a = 0.0, d_s = 0.0;
      const double p = lookups.pitch_response.smoothPitch(a, s, &d_a, &d_s);
      const double fd_a = (lookups.pitch_response.smoothPitch(a + h, s) -
                           lookups.pitch_response.smoothPitch(a - h, s)) /
                          (2 * h);
      const double fd_s = (lookups.pitch_response.smoothPitch(a, s + h) -
                           lookups.pitch_response.smoothPitch(a, s - h)) /
                          (2 * h);
      EXPECT_NEAR(d_a, fd_a, 1e-5) << a << " " << d;
      EXPECT_NEAR(d_s, fd_s, 1e-5) << a << " " << d;
      if (std::abs(a) <= 2.0 && std::abs(d) <= 20.0) {
        worst_departure =
            std::max(worst_departure, std::abs(p - lookups.pitch_response.pitch(a, s)));
      }
    }
  }
  EXPECT_LT(worst_departure, 0.3 * deg);
  // Through the grid values.
  EXPECT_NEAR(lookups.pitch_response.smoothPitch(0.5, 10.0 * deg),
              lookups.pitch_response.pitch(0.5, 10.0 * deg), 1e-12);
  for (double d = -24.0; d <= 24.0; d += 0.11) {
    const double s = d * deg;
    double dv = 0.0, da = 0.0;
    lookups.bounds.optimiserSpeedLimit(s, &dv);
    lookups.bounds.optimiserAccelerationLimit(s, &da);
    const double near_knot = std::remainder(d, 1.0);  // knots at whole degrees
    if (std::abs(near_knot) < 1e-3) continue;         // the difference straddles a corner's edge
    EXPECT_NEAR(
        dv,
        (lookups.bounds.optimiserSpeedLimit(s + h) - lookups.bounds.optimiserSpeedLimit(s - h)) /
            (2 * h),
        1e-4)
        << d;
    EXPECT_NEAR(da,
                (lookups.bounds.optimiserAccelerationLimit(s + h) -
                 lookups.bounds.optimiserAccelerationLimit(s - h)) /
                    (2 * h),
                1e-4)
        << d;
  }
}

// The searches' pitch table of the look-ups: never faster than the bound at any slope, within
// a bin's worth of it, 0 where the Segway cannot drive; with a user's table, the lower of both.
TEST(SegwayLookups, TheSearchesTableIsNeverFasterThanTheBound) {
  const SegwaySlopeBounds& bounds = defaultSegwayLookups().bounds;
  const double bin = 0.25 * M_PI / 180.0;
  const PitchSpeedTable table = slopeSpeedTable(bounds, nullptr, bin);
  double worst_gap = 0.0;
  for (int i = -4000; i <= 4000; ++i) {
    const double slope = i * 0.5 * M_PI / 180.0 / 100.0;  // -20..20 deg and beyond
    const double exact = bounds.speedLimit(slope);
    ASSERT_LE(table.lookup(slope), exact + 1e-12) << slope;
    worst_gap = std::max(worst_gap, exact - table.lookup(slope));
  }
  // The steepest piece of the defaults: 1 m/s over 3 deg.
  EXPECT_LE(worst_gap, bin * (1.0 / (3.0 * M_PI / 180.0)) + 1e-9);
  EXPECT_EQ(table.lookup(21.0 * M_PI / 180.0), 0.0);
  EXPECT_EQ(table.lookup(-30.0 * M_PI / 180.0), 0.0);
  EXPECT_DOUBLE_EQ(table.lookup(0.01), 3.5);

  const PitchSpeedTable user(BinEdges({-0.3, 0.0, 0.05, 0.3}, "user"), {2.0, 0.8, 3.0});
  const PitchSpeedTable both = slopeSpeedTable(bounds, &user, bin);
  for (int i = -400; i <= 400; ++i) {
    const double slope = i * 0.001;
    EXPECT_LE(both.lookup(slope), std::min(user.lookup(slope), bounds.speedLimit(slope)) + 1e-12);
  }
  EXPECT_DOUBLE_EQ(both.lookup(0.02), 0.8);
  EXPECT_DOUBLE_EQ(both.lookup(-0.02), 2.0);
  EXPECT_THROW(slopeSpeedTable(bounds, nullptr, 0.0), InputError);
}

// Straight up a ramp of `slope` along +x from rest-free speed v0 with acceleration a, rows
// every 0.1 s, the attitude columns from the point model (what a solver would write).
Trajectory straightUp(const TerrainFollowingModel& vehicle, double slope, double v0, double a) {
  Trajectory trajectory;
  AttitudeWorkspace workspace;
  AttitudeResult attitude;
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * i;
    TrajectorySample s{};
    s.t = t;
    s.x = 5.0 + (v0 * t + 0.5 * a * t * t) * std::cos(slope);
    s.y = 10.0;
    s.v = v0 + a * t;
    EXPECT_EQ(vehicle.compute({s.x, s.y, 0.0}, workspace, attitude), AttitudeStatus::kOk);
    s.z = attitude.attitude.z;
    s.roll = attitude.attitude.roll;
    s.pitch = attitude.attitude.pitch;
    trajectory.samples.push_back(s);
  }
  return trajectory;
}

// The independent check holds a Segway to its look-ups when given them: no speed beyond the
// slope's bound (0 beyond 20 deg), and the platform pitch of its acceleration within pitch_max.
TEST(SegwayLookups, TheIndependentCheckHoldsThem) {
  const SegwayLookups lookups = defaultSegwayLookups();
  TrajectoryRequirements r;
  r.limits.v_max = 2.0;
  r.limits.a_max = 1.0;
  r.limits.pitch_max = r.limits.roll_max = 0.6;
  r.segway = &lookups;
  const auto check = [&](double slope, double v0, double a) {
    const ElevationMap map = ramp(slope);
    const TerrainSurface surface(map, Interpolation::kBicubic);
    const PointAttitudeModel vehicle(surface);
    r.vehicle = &vehicle;
    return checkTrajectory(straightUp(vehicle, slope, v0, a), r);
  };
  EXPECT_TRUE(check(10.0 * M_PI / 180.0, 0.5, 0.0).ok()) << check(0.17, 0.5, 0.0).summary();
  const CheckReport steep = check(22.0 * M_PI / 180.0, 0.5, 0.0);
  ASSERT_NE(steep.find("segway_slope_v_max"), nullptr) << steep.summary();
  EXPECT_NE(check(22.0 * M_PI / 180.0, 0.5, 0.1).find("segway_slope_a_max"), nullptr);  // 0 there
  EXPECT_EQ(steep.find("pitch_max"), nullptr);  // within 0.6 rad: the look-ups alone fail it
  // Accelerating at 0.5 m/s^2 on the level leans the platform by atan(0.5 / 9.81) = 0.051 rad.
  r.limits.pitch_max = 0.1;
  EXPECT_TRUE(check(0.0, 0.2, 0.5).ok()) << check(0.0, 0.2, 0.5).summary();
  r.limits.pitch_max = 0.04;
  const CheckReport leaning = check(0.0, 0.2, 0.5);
  ASSERT_NE(leaning.find("segway_platform_pitch"), nullptr) << leaning.summary();
  EXPECT_NEAR(leaning.find("segway_platform_pitch")->value, std::atan(0.5 / 9.81), 2e-3);
  // Without the look-ups, the same trajectory passes.
  r.segway = nullptr;
  EXPECT_TRUE(check(0.0, 0.2, 0.5).ok());
}

TEST(SegwayRmpModel, ClimbsARampAlongItsPlane) {
  const double slope = 10.0 * M_PI / 180.0;
  const ElevationMap map = ramp(slope);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const SegwayRmpModel model(surface);
  const SegwayState state{5.0, 10.0, 0.0, 1.0, 0.0};
  SegwayState end;
  ASSERT_TRUE(model.propagate(state, Eigen::Vector2d::Zero(), 0.5, end));
  // 0.5 m along a 10 degree slope: 0.5 cos(10 deg) m of map distance.
  EXPECT_NEAR(end.x - 5.0, 0.5 * std::cos(slope), 1e-6);
  EXPECT_NEAR(end.y, 10.0, 1e-9);
  const std::optional<SegwayPose> pose = model.pose(state, 0.0);
  ASSERT_TRUE(pose);
  EXPECT_NEAR(pose->slope, slope, 1e-6);
  EXPECT_LT(pose->platform_pitch, 0.0);  // leans into the hill
  EXPECT_FALSE(model.propagate({19.9, 10.0, 0.0, 1.0, 0.0}, Eigen::Vector2d::Zero(), 0.5, end));
}

TEST(SegwayRmpModel, ReportsEachConstraint) {
  const ElevationMap flat = ramp(0.0);
  const TerrainSurface surface(flat, Interpolation::kBilinear);
  const SegwayRmpModel model(surface);
  const auto check = [&](const SegwayState& s, const Eigen::Vector2d& u) {
    return model.check(s, u, *model.pose(s, u.x()));
  };
  EXPECT_TRUE(check({5, 5, 0, 1.0, 0.5}, {0.5, 0.0}).ok());
  // (1) curvature: at 3 m/s kappa_max = 2 / 9, omega <= 0.667.
  EXPECT_NEAR(check({5, 5, 0, 3.0, 1.0}, {0, 0}).curvature, 1.0 - 3.0 * 2.0 / 9.0, 1e-12);
  // (1) curvature rate: |omega' - v' kappa| <= v sigma_max = 2.
  EXPECT_NEAR(check({5, 5, 0, 1.0, 0.0}, {0.0, 3.0}).curvature_rate, 1.0, 1e-12);
  // (5) speed and (6) acceleration.
  EXPECT_NEAR(check({5, 5, 0, 4.0, 0.0}, {0, 0}).speed, 0.5, 1e-12);
  EXPECT_NEAR(check({5, 5, 0, 1.0, 0.0}, {2.5, 0}).acceleration, 0.5, 1e-12);
  // (3) platform pitch: braking hard downhill pitches back beyond the limit with a tight limit.
  SegwayLimits tight;
  tight.pitch_max = 0.1;
  const SegwayRmpModel strict(surface, defaultSegwayLookups(), tight);
  const SegwayState s{5, 5, 0, 1.0, 0.0};
  EXPECT_GT(strict.check(s, {-2.0, 0}, *strict.pose(s, -2.0)).pitch, 0.0);
  // (4) roll and the climbing limit on a 25 degree ramp.
  const ElevationMap steep = ramp(25.0 * M_PI / 180.0);
  const TerrainSurface steep_surface(steep, Interpolation::kBilinear);
  const SegwayRmpModel on_steep(steep_surface);
  const SegwayState across{5, 10, M_PI / 2, 0.5, 0.0};
  EXPECT_GT(on_steep.check(across, {0, 0}, *on_steep.pose(across, 0)).roll, 0.0);
  const SegwayState up{5, 10, 0.0, 0.5, 0.0};
  EXPECT_NEAR(on_steep.check(up, {0, 0}, *on_steep.pose(up, 0)).speed, 0.5, 1e-12);
}

}  // namespace
}  // namespace terratraj::models
