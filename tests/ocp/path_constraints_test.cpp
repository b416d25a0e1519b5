#include "terratraj/ocp/path_constraints.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/finite_difference.hpp"
#include "terratraj/models/segway_lookups.hpp"

namespace terratraj::ocp {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// A point from p = (x, y, heading, v, omega, v', omega'), with a made-up attitude of (x, y,
// heading) and its exact Jacobian: pitch (along the heading) up to about 19 deg either way,
// roll up to about 10 deg.
PathPoint pointAt(const Eigen::VectorXd& p) {
  PathPoint point;
  point.state = p.head<3>();
  point.v = p(3);
  point.omega = p(4);
  point.v_dot = p(5);
  point.omega_dot = p(6);
  const double x = p(0), y = p(1), heading = p(2);
  point.attitude.attitude.pitch = 0.3 * std::cos(0.7 * y) * std::sin(heading) + 0.03 * x;
  point.attitude.attitude.roll = 0.1 * std::sin(x) + 0.05 * y;
  point.attitude.jacobian.setZero();
  point.attitude.jacobian.row(1) << 0.1 * std::cos(x), 0.05, 0.0;
  point.attitude.jacobian.row(2) << 0.03, -0.21 * std::sin(0.7 * y) * std::sin(heading),
      0.3 * std::cos(0.7 * y) * std::cos(heading);
  return point;
}

// Every row's derivative by the point's variables, the Segway's rows and a pitch table among
// them, against central differences, at points on slopes across the look-ups' grid (corners,
// the drivable edge and beyond it included).
TEST(PathConstraints, EveryRowsDerivativeMatchesFiniteDifferences) {
  models::VehicleLimits limits;
  limits.pitch_max = 25.0 * kDegree;
  const models::SegwayLookups segway = models::defaultSegwayLookups();
  const models::PitchSpeedTable pitch_table(
      models::BinEdges({-0.4, -0.1, 0.0, 0.15, 0.4}, "test pitch table"), {0.5, 0.9, 1.0, 0.7});
  SpeedTables tables;
  tables.pitch = &pitch_table;
  tables.segway = &segway;
  for (const double scale : {1.0, 0.97}) {
    const PathConstraints constraints(limits, tables, scale);
    ASSERT_EQ(constraints.count(), 14 + 1 + kSegwayPathRows);
    EXPECT_EQ(std::string(constraints.name(14)), "table_pitch");
    EXPECT_EQ(std::string(constraints.name(15)), "segway_slope_v_max");
    EXPECT_EQ(std::string(constraints.name(17)), "segway_slope_a_max");
    EXPECT_EQ(std::string(constraints.name(19)), "segway_platform_pitch");
    const auto values = [&](const Eigen::VectorXd& p) {
      Eigen::VectorXd g(constraints.count());
      constraints.evaluate(pointAt(p), g.data(), nullptr);
      return g;
    };
    for (const double x : {-6.0, 1.0, 6.5}) {
      for (const double heading : {0.4, 1.3, -1.1, 2.9}) {
        Eigen::VectorXd p(kPathVariables);
        p << x, 0.8, heading, 0.6, 0.2, 0.35, -0.1;
        Eigen::Matrix<double, Eigen::Dynamic, kPathVariables> jacobian;
        Eigen::VectorXd g(constraints.count());
        constraints.evaluate(pointAt(p), g.data(), &jacobian);
        EXPECT_TRUE((g - values(p)).isZero(0.0));
        SCOPED_TRACE("x " + std::to_string(x) + ", heading " + std::to_string(heading) +
                     ", pitch " + std::to_string(pointAt(p).attitude.attitude.pitch / kDegree) +
                     " deg");
        EXPECT_TRUE(testing::matchesFiniteDifferences(
            jacobian, testing::centralDifferences(values, p, 1e-6), 1e-6, 1e-5));
      }
    }
  }
}

// Where the Segway's rows hold, its look-ups hold (their C1 versions never exceed the grids'
// bounds but near the platform pitch's 0.3 deg): speed and acceleration by slope, the platform
// pitch; and the rows are broken where the look-ups are.
TEST(PathConstraints, TheSegwaysRowsHoldItsLookups) {
  models::VehicleLimits limits;
  limits.pitch_max = 25.0 * kDegree;
  const models::SegwayLookups segway = models::defaultSegwayLookups();
  SpeedTables tables;
  tables.segway = &segway;
  const PathConstraints constraints(limits, tables);
  const int row = constraints.count() - kSegwayPathRows;
  std::vector<double> g(static_cast<std::size_t>(constraints.count()));
  int held = 0, broken = 0;
  for (double slope = -24.0; slope <= 24.0; slope += 0.37) {
    for (double v = 0.0; v <= 1.0; v += 0.05) {
      for (double a = -0.5; a <= 0.5; a += 0.125) {
        PathPoint point;
        point.v = v;
        point.v_dot = a;
        point.attitude.attitude.pitch = slope * kDegree;
        constraints.evaluate(point, g.data(), nullptr);
        const auto at = [&](int k) { return g[static_cast<std::size_t>(row + k)]; };
        const double s = slope * kDegree;
        if (at(0) <= 0.0 && at(1) <= 0.0 && at(2) <= 0.0 && at(3) <= 0.0 && at(4) <= 0.0) {
          ++held;
          EXPECT_LE(v, segway.bounds.speedLimit(s) + 1e-12) << slope << " deg";
          EXPECT_LE(std::abs(a), segway.bounds.accelerationLimit(s) + 1e-12) << slope << " deg";
          EXPECT_LE(std::abs(segway.pitch_response.pitch(a, s)), limits.pitch_max + 0.3 * kDegree);
        }
        if (v > segway.bounds.speedLimit(s) + 1e-9) {
          ++broken;
          EXPECT_GT(at(0), 0.0) << slope << " deg, v " << v;
        }
      }
    }
  }
  EXPECT_GT(held, 100);
  EXPECT_GT(broken, 100);
}

}  // namespace
}  // namespace terratraj::ocp
