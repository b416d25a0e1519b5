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
