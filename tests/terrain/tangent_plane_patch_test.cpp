#include "terratraj/terrain/tangent_plane_patch.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_maps.hpp"

namespace terratraj::terrain {
namespace {

TEST(TangentPlanePatch, FrameIsOrthonormalRightHandedAndAlongTheHeading) {
  const ElevationMap map = testing::smoothMap(30, 30, 0.5);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  for (double heading = -3.0; heading < 3.2; heading += 0.7) {
    const TangentPlanePatch patch = *TangentPlanePatch::at(surface, {7.3, 6.1}, heading);
    const Eigen::Matrix3d& R = patch.rotation();
    EXPECT_TRUE((R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(std::remainder(patch.heading() - heading, 2 * M_PI), 0.0, 1e-12);
    EXPECT_TRUE(patch.normal().isApprox(surface.sample({7.3, 6.1})->normal(), 1e-12));
    EXPECT_NEAR(patch.origin().z(), *surface.height({7.3, 6.1}), 1e-12);
  }
}

TEST(TangentPlanePatch, PitchAndRollFollowTheConventions) {
  // A plane rising toward +x at 10 degrees.
  const double slope = 10.0 * M_PI / 180.0;
  const ElevationMap map = testing::planeMap(20, 20, 1.0, std::tan(slope), 0.0, 0.0);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const Eigen::Vector2d p(10.0, 10.0);
  // Heights are stored as float: angles agree to about 1e-8.
  // Facing uphill: nose up.
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, 0.0)->pitch(), slope, 1e-7);
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, 0.0)->roll(), 0.0, 1e-7);
  // Facing downhill: nose down.
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, M_PI)->pitch(), -slope, 1e-7);
  // Facing north: the slope rises to the right (east), so the left side is lower: roll < 0.
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, M_PI / 2)->roll(), -slope, 1e-7);
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, M_PI / 2)->pitch(), 0.0, 1e-7);
  // Facing south: left side (east) higher.
  EXPECT_NEAR(TangentPlanePatch::at(surface, p, -M_PI / 2)->roll(), slope, 1e-7);
}

TEST(TangentPlanePatch, RotationIsYawPitchRollProduct) {
  const ElevationMap map = testing::smoothMap(30, 30, 0.5);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const TangentPlanePatch patch = *TangentPlanePatch::at(surface, {4.2, 9.9}, 0.8);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(patch.heading(), Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(-patch.pitch(), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(patch.roll(), Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(patch.rotation().isApprox(expected, 1e-12));
}

TEST(TangentPlanePatch, PointsStayOnAPlanarSurfaceAndTransformsCompose) {
  const ElevationMap map = testing::planeMap(20, 20, 1.0, 0.2, -0.1, 3.0);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const TangentPlanePatch first = *TangentPlanePatch::at(surface, {5.0, 5.0}, 0.4);
  // Move 0.3 m along a direction 0.2 rad left of T, then enter the next patch.
  const PatchPose end{0.3 * std::cos(0.2), 0.3 * std::sin(0.2), 0.2};
  const Eigen::Vector3d end_point = first.toMap(end.u, end.w);
  EXPECT_NEAR(end_point.z(), *surface.height(end_point.head<2>()), 1e-9);  // still on the plane
  const TangentPlanePatch second = *first.next(surface, end);
  EXPECT_TRUE(second.origin().isApprox(end_point, 1e-12));
  EXPECT_NEAR(second.heading(), first.mapHeadingOf(0.2), 1e-12);
  // The transform maps the end point (in the first frame) to the second's origin.
  const Eigen::Vector3d in_first(end.u, end.w, 0.0);
  EXPECT_LT((first.transformTo(second) * in_first).norm(), 1e-12);
  // On one plane the motion direction becomes the new T.
  const Eigen::Vector3d direction =
      std::cos(0.2) * first.tangent() + std::sin(0.2) * first.lateral();
  EXPECT_TRUE(second.tangent().isApprox(direction, 1e-12));
}

TEST(TangentPlanePatch, NoPatchOffTheMap) {
  const ElevationMap map = testing::smoothMap(10, 10, 1.0);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  EXPECT_FALSE(TangentPlanePatch::at(surface, {-1.0, 5.0}, 0.0));
  const TangentPlanePatch patch = *TangentPlanePatch::at(surface, {9.5, 5.0}, 0.0);
  EXPECT_FALSE(patch.next(surface, {2.0, 0.0, 0.0}));  // drives off the east edge
}

}  // namespace
}  // namespace terratraj::terrain
