#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "common/finite_difference.hpp"
#include "terratraj/models/four_wheel_attitude_model.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/terrain/clearance_map.hpp"
#include "terratraj/terrain/tangent_plane_patch.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::models {
namespace {

using terrain::ElevationMap;
using terrain::Interpolation;
using terrain::TerrainSurface;

ElevationMap planeMap(double a, double b) {
  terrain::GridGeometry g;
  g.rows = g.cols = 40;
  g.cell = 0.25;
  ElevationMap map(g);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector2d p = g.cellCenter({r, c});
      map.elevation()(r, c) = static_cast<float>(a * p.x() + b * p.y());
    }
  }
  return map;
}

ElevationMap roughMap() {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kHills;
  options.rows = options.cols = 96;
  options.cell = 0.25;
  options.seed = 4;
  return terrain::generateTerrain(options);
}

// Central finite differences of (z, roll, pitch) by (x, y, heading), each attitude computed
// from a cold start.
Eigen::Matrix3d finiteDifferenceJacobian(const TerrainFollowingModel& model, const PlanarPose& pose,
                                         double h) {
  const auto attitude = [&](const Eigen::VectorXd& at) {
    AttitudeWorkspace workspace;  // cold
    AttitudeResult a;
    EXPECT_EQ(model.compute({at(0), at(1), at(2)}, workspace, a), AttitudeStatus::kOk);
    return Eigen::Vector3d(a.attitude.z, a.attitude.roll, a.attitude.pitch);
  };
  return terratraj::testing::centralDifferences(attitude,
                                                Eigen::Vector3d(pose.x, pose.y, pose.heading), h);
}

std::vector<PlanarPose> randomPoses(int count, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> position(lo, hi), heading(-M_PI, M_PI);
  std::vector<PlanarPose> poses;
  for (int i = 0; i < count; ++i) poses.push_back({position(rng), position(rng), heading(rng)});
  return poses;
}

TEST(PointAttitudeModel, MatchesTheTangentPlanePatch) {
  const ElevationMap map = roughMap();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel model(surface);
  AttitudeWorkspace workspace;
  for (const PlanarPose& pose : randomPoses(50, 2.0, 22.0, 1)) {
    AttitudeResult result;
    ASSERT_EQ(model.compute(pose, workspace, result), AttitudeStatus::kOk);
    const auto patch = terrain::TangentPlanePatch::at(surface, {pose.x, pose.y}, pose.heading);
    EXPECT_NEAR(result.attitude.pitch, patch->pitch(), 1e-12);
    EXPECT_NEAR(result.attitude.roll, patch->roll(), 1e-12);
    EXPECT_NEAR(result.attitude.z, patch->origin().z(), 1e-12);
  }
}

TEST(AttitudeModels, JacobiansMatchFiniteDifferences) {
  const ElevationMap map = roughMap();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  RockerBogieSolverOptions precise;
  precise.tolerance = 1e-12;
  const PointAttitudeModel point(surface);
  const FourWheelAttitudeModel four_wheel(surface, FourWheelGeometry{});
  const RockerBogieAttitudeModel rocker_bogie(surface, RockerBogieGeometry{}, precise);
  for (const TerrainFollowingModel* model :
       std::initializer_list<const TerrainFollowingModel*>{&point, &four_wheel, &rocker_bogie}) {
    int checked = 0;
    for (const PlanarPose& pose : randomPoses(40, 2.0, 22.0, 2)) {
      AttitudeWorkspace workspace;
      AttitudeResult result;
      if (model->compute(pose, workspace, result) != AttitudeStatus::kOk) continue;
      const Eigen::Matrix3d fd = finiteDifferenceJacobian(*model, pose, 1e-6);
      const double scale = std::max(1.0, result.jacobian.cwiseAbs().maxCoeff());
      EXPECT_LT((result.jacobian - fd).cwiseAbs().maxCoeff(), 2e-5 * scale)
          << model->name() << " at (" << pose.x << ", " << pose.y << ", " << pose.heading
          << ")\nanalytic\n"
          << result.jacobian << "\nfinite differences\n"
          << fd;
      ++checked;
    }
    EXPECT_GE(checked, 35) << model->name();
  }
}

TEST(AttitudeModels, AllAgreeOnAPlane) {
  const double a = 0.15, b = -0.1;
  const ElevationMap map = planeMap(a, b);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const PointAttitudeModel point(surface);
  const FourWheelAttitudeModel four_wheel(surface, FourWheelGeometry{});
  const RockerBogieAttitudeModel rocker_bogie(surface);
  for (const PlanarPose& pose : randomPoses(20, 3.0, 7.0, 3)) {
    AttitudeWorkspace w1, w2, w3;
    AttitudeResult p, f, r;
    ASSERT_EQ(point.compute(pose, w1, p), AttitudeStatus::kOk);
    ASSERT_EQ(four_wheel.compute(pose, w2, f), AttitudeStatus::kOk);
    ASSERT_EQ(rocker_bogie.compute(pose, w3, r), AttitudeStatus::kOk);
    EXPECT_NEAR(f.attitude.pitch, p.attitude.pitch, 1e-6);
    EXPECT_NEAR(f.attitude.roll, p.attitude.roll, 1e-6);
    EXPECT_NEAR(f.attitude.z, p.attitude.z, 1e-5);
    EXPECT_NEAR(r.attitude.pitch, p.attitude.pitch, 1e-6);
    EXPECT_NEAR(r.attitude.roll, p.attitude.roll, 1e-6);
    EXPECT_LT(r.suspension.cwiseAbs().maxCoeff(), 1e-6);  // a plane needs no articulation
  }
}

TEST(RockerBogieAttitudeModel, AllSixWheelsTouchTheTerrain) {
  const ElevationMap map = roughMap();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const RockerBogieAttitudeModel model(surface);
  AttitudeWorkspace workspace;
  int articulated = 0;
  for (const PlanarPose& pose : randomPoses(100, 2.0, 22.0, 5)) {
    AttitudeResult result;
    if (model.compute(pose, workspace, result) != AttitudeStatus::kOk) continue;
    EXPECT_LT(result.contact_residual, 1e-6);
    // Independent check: place the wheels with Eigen's rotations and measure their clearance.
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(pose.heading, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(-result.attitude.pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(result.attitude.roll, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Matrix<double, 3, 6> wheels = model.wheelCentresInBody(result.suspension);
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector3d centre =
          Eigen::Vector3d(pose.x, pose.y, result.attitude.z) + rotation * wheels.col(k);
      const auto ground = surface.sample(centre.head<2>());
      ASSERT_TRUE(ground);
      const double clearance = centre.z() - ground->height;
      EXPECT_NEAR(clearance, 0.065 * std::sqrt(1 + ground->gradient.squaredNorm()), 1e-3);
    }
    articulated += result.suspension.cwiseAbs().maxCoeff() > 0.01;
  }
  EXPECT_GT(articulated, 10);  // rough terrain really bends the suspension
}

TEST(RockerBogieAttitudeModel, WarmStartSavesIterations) {
  const ElevationMap map = roughMap();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const RockerBogieAttitudeModel model(surface);
  AttitudeWorkspace warm;
  int warm_iterations = 0, cold_iterations = 0;
  for (int i = 0; i < 200; ++i) {
    const PlanarPose pose{4.0 + 0.01 * i, 10.0 + 0.004 * i, 0.3 + 0.002 * i};
    AttitudeResult result;
    ASSERT_EQ(model.compute(pose, warm, result), AttitudeStatus::kOk);
    if (i > 0) warm_iterations += result.iterations;
    AttitudeWorkspace cold;
    ASSERT_EQ(model.compute(pose, cold, result), AttitudeStatus::kOk);
    if (i > 0) cold_iterations += result.iterations;
  }
  EXPECT_LT(warm_iterations, cold_iterations);
}

TEST(AttitudeModels, OffTheMapOrOverNoDataIsAStatusNotACrash) {
  ElevationMap map = roughMap();
  map.elevation()(40, 40) = std::numeric_limits<float>::quiet_NaN();
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel point(surface);
  const FourWheelAttitudeModel four_wheel(surface, FourWheelGeometry{});
  const RockerBogieAttitudeModel rocker_bogie(surface);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const TerrainFollowingModel* model :
       std::initializer_list<const TerrainFollowingModel*>{&point, &four_wheel, &rocker_bogie}) {
    AttitudeWorkspace workspace;
    AttitudeResult result;
    EXPECT_EQ(model->compute({-5.0, 3.0, 0.0}, workspace, result), AttitudeStatus::kNoTerrain);
    if (model != &point) {  // wheels hang over the west edge; the point itself is on the map
      EXPECT_EQ(model->compute({0.05, 12.0, 0.0}, workspace, result), AttitudeStatus::kNoTerrain)
          << model->name();
    }
    EXPECT_EQ(model->compute({10.125, 10.125, 0.0}, workspace, result), AttitudeStatus::kNoTerrain);
    EXPECT_EQ(model->compute({nan, 3.0, 0.0}, workspace, result), AttitudeStatus::kNoTerrain);
  }
}

// The clearance the refiner keeps beside no data (terrain::ClearanceMap with the surface's
// stencil reach, less the model's sampling radius) is where the model can be placed: every pose
// with a positive clearance, at any heading, rests on the surface, and the bound is tight (poses
// up to 10 cm inside it fail).
TEST(AttitudeModels, ThePositiveClearanceBesideNoDataIsWhereTheModelCanBePlaced) {
  ElevationMap map = roughMap();
  for (int r = 40; r <= 42; ++r) map.elevation()(r, 50) = std::numeric_limits<float>::quiet_NaN();
  const TerrainSurface surface(map, Interpolation::kCubicBSpline);
  const PointAttitudeModel point(surface);
  const FourWheelAttitudeModel four_wheel(surface, FourWheelGeometry{});
  const RockerBogieAttitudeModel rocker_bogie(surface);
  const double centre_x = map.geometry().cellCenter({41, 50}).x();
  const double centre_y = map.geometry().cellCenter({41, 50}).y();
  for (const TerrainFollowingModel* model :
       std::initializer_list<const TerrainFollowingModel*>{&point, &four_wheel, &rocker_bogie}) {
    SCOPED_TRACE(model->name());
    const terrain::ClearanceMap clearance(map, 1e3, surface.stencilReach(),
                                          model->samplingRadius());
    int placed = 0, failed_within = 0;
    for (const PlanarPose& pose : randomPoses(20000, -2.5, 2.5, 7)) {
      const PlanarPose at{centre_x + pose.x, centre_y + pose.y, pose.heading};
      const std::optional<terrain::Clearance> c = clearance.at({at.x, at.y});
      ASSERT_TRUE(c.has_value());
      AttitudeWorkspace workspace;
      AttitudeResult result;
      const AttitudeStatus status = model->compute(at, workspace, result);
      if (c->distance > 1e-9) {
        EXPECT_NE(status, AttitudeStatus::kNoTerrain) << at.x << ", " << at.y << ", " << at.heading;
        ++placed;
      } else if (c->distance > -0.1 && status == AttitudeStatus::kNoTerrain) {
        ++failed_within;
      }
    }
    EXPECT_GT(placed, 1000);
    EXPECT_GT(failed_within, 10);
  }
}

TEST(RockerBogieAttitudeModel, ACliffIsNoContact) {
  // A 1 m step across the middle wheels' path: no configuration of the suspension rests on it.
  terrain::GridGeometry g;
  g.rows = g.cols = 40;
  g.cell = 0.05;
  ElevationMap map(g);
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 20; c < g.cols; ++c) map.elevation()(r, c) = 1.0f;
  }
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const RockerBogieAttitudeModel model(surface);
  AttitudeWorkspace workspace;
  AttitudeResult result;
  EXPECT_EQ(model.compute({1.0, 1.0, 0.0}, workspace, result), AttitudeStatus::kNoContact);
}

}  // namespace
}  // namespace terratraj::models
