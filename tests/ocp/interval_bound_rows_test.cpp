// IntervalBoundRows: when its rows and the nodes hold, v and omega hold their limits on the
// whole interval, as the re-simulation integrates them (the exact integral of the interpolated
// controls); and they catch the overshoots the nodes alone miss.
#include "terratraj/ocp/interval_bound_rows.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "common/finite_difference.hpp"
#include "terratraj/bench/problem_sets.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/ocp/transcription_nlp.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::ocp {
namespace {

struct Limits {
  double v_max = 1.0, omega_max = 0.8, kappa_max = 1.0;
};

// The largest excess of the four limits at (v, omega) (<= 0: within them).
double excess(double v, double omega, const Limits& l) {
  return std::max(
      {v - l.v_max, -v, std::abs(omega) - l.omega_max, std::abs(omega) - l.kappa_max * v});
}

// One interval of `scheme` with random nodes, controls and duration; whether the rows and the
// nodes hold, and the worst excess of the exactly integrated v(t), omega(t) over the interval.
struct Sample {
  bool rows_and_nodes_hold = false;
  bool nodes_hold = false;
  double worst_between = 0.0;
  double control_point_error = 0.0;  ///< |v_max rows + v_max - the polynomial's control points|
};

Sample drawInterval(TranscriptionScheme scheme, const Limits& limits, bool longer,
                    std::mt19937& random) {
  std::uniform_real_distribution<double> speed(0.0, 1.1), yaw(-1.0, 1.0), control(-4.0, 4.0),
      duration(0.02, 0.6);
  models::VehicleLimits vehicle;
  vehicle.v_max = limits.v_max;
  vehicle.omega_max = limits.omega_max;
  vehicle.kappa_max = limits.kappa_max;
  const double tf = duration(random);
  // Rows built for final times up to tf_rows >= tf (the guarantee) or below it (none).
  const double tf_rows = tf * (longer ? 1.5 : 1.0);
  const IntervalBoundRows rows(scheme, {0.0, 1.0}, vehicle, tf_rows);
  const bool hs = scheme == TranscriptionScheme::kHermiteSimpson;
  const int points = hs ? 3 : 2;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(kPointSize * points + 1);
  x(kPointSize * points) = tf;
  const Eigen::Vector2d z0(speed(random), yaw(random));
  Eigen::Vector2d u[3];
  for (Eigen::Vector2d& c : u) c = Eigen::Vector2d(control(random), control(random));
  // The end node: the exact integral of the controls (Simpson is exact for quadratics).
  const Eigen::Vector2d z1 = hs ? Eigen::Vector2d(z0 + tf / 6.0 * (u[0] + 4.0 * u[1] + u[2]))
                                : Eigen::Vector2d(z0 + tf / 2.0 * (u[0] + u[1]));
  for (int p = 0; p < points; ++p) {
    const Eigen::Vector2d z = p == 0 ? z0 : p == points - 1 ? z1 : 0.5 * (z0 + z1);
    x.segment<2>(kPointSize * p + 3) = z;
    x.segment<2>(kPointSize * p + 5) = hs ? u[p] : u[p == 0 ? 0 : 1];
  }
  std::vector<double> g(static_cast<std::size_t>(rows.count()));
  rows.evaluate(x, g.data());
  Sample out;
  out.nodes_hold = excess(z0.x(), z0.y(), limits) <= 0.0 && excess(z1.x(), z1.y(), limits) <= 0.0;
  out.rows_and_nodes_hold = out.nodes_hold && *std::max_element(g.begin(), g.end()) <= 0.0;
  // The verifier's integral of the interpolated controls over the first fraction s.
  const auto zAt = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return hs ? Eigen::Vector2d(z0 + tf * ((2.0 * s3 / 3.0 - 1.5 * s2 + s) * u[0] -
                                           4.0 * (s3 / 3.0 - s2 / 2.0) * u[1] +
                                           (2.0 * s3 / 3.0 - s2 / 2.0) * u[2]))
              : Eigen::Vector2d(z0 + tf * (s * u[0] + 0.5 * s2 * (u[1] - u[0])));
  };
  out.worst_between = -1e300;
  for (int i = 0; i <= 1000; ++i) {
    const Eigen::Vector2d z = zAt(i / 1000.0);
    out.worst_between = std::max(out.worst_between, excess(z.x(), z.y(), limits));
  }
  // Exact rows (T = t_f): the v_max rows (the first of each control point) at the Bezier
  // control points of v(s), from the polynomial's end slopes (a degree-n polynomial's first
  // and last inner control points are p(0) + p'(0) / n and p(1) - p'(1) / n).
  if (!longer) {
    const double e = 1e-5, n = hs ? 3.0 : 2.0;
    const double slope0 = (zAt(e).x() - zAt(-e).x()) / (2.0 * e);
    const double slope1 = (zAt(1.0 + e).x() - zAt(1.0 - e).x()) / (2.0 * e);
    out.control_point_error = std::abs(g[0] + limits.v_max - (zAt(0.0).x() + slope0 / n));
    if (hs) {
      out.control_point_error = std::max(
          out.control_point_error, std::abs(g[1] + limits.v_max - (zAt(1.0).x() - slope1 / n)));
    }
  }
  return out;
}

TEST(IntervalBoundRows, HoldTheLimitsOnTheWholeIntervalAndCatchOvershoots) {
  const Limits limits;
  for (TranscriptionScheme scheme :
       {TranscriptionScheme::kHermiteSimpson, TranscriptionScheme::kTrapezoidal}) {
    for (bool longer : {false, true}) {  // rows for the interval's final time, or a longer one
      SCOPED_TRACE(std::string(transcriptionSchemeName(scheme)) + (longer ? " longer" : ""));
      std::mt19937 random(11);
      int held = 0, overshoots_caught = 0;
      for (int trial = 0; trial < 20000; ++trial) {
        const Sample s = drawInterval(scheme, limits, longer, random);
        ASSERT_LT(s.control_point_error, 1e-8) << "trial " << trial;
        if (s.rows_and_nodes_hold) {
          ++held;
          ASSERT_LE(s.worst_between, 1e-12) << "trial " << trial;
        } else if (s.nodes_hold && s.worst_between > 1e-3) {
          ++overshoots_caught;  // the nodes hold, the interval does not: the rows said so
        }
      }
      // Neither side of the test is empty.
      EXPECT_GT(held, 200);
      EXPECT_GT(overshoots_caught, 200);
    }
  }
}

// The rows are linear: their Jacobian (constant) against differences of their values.
TEST(IntervalBoundRows, JacobianMatchesDifferences) {
  models::VehicleLimits limits;
  limits.omega_max = 0.8;
  const IntervalBoundRows rows(TranscriptionScheme::kHermiteSimpson, uniformMesh(3), limits, 2.0);
  std::vector<int> r, c;
  rows.appendStructure(0, r, c);
  std::vector<double> values(r.size());
  rows.jacobian(values.data());
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(rows.count(), 7 * kPointSize + 1);
  for (std::size_t i = 0; i < r.size(); ++i) jacobian(r[i], c[i]) += values[i];
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd x(7 * kPointSize + 1);
  for (int i = 0; i < x.size(); ++i) x(i) = unit(random);
  const auto g = [&](const Eigen::VectorXd& at) {
    Eigen::VectorXd out(rows.count());
    rows.evaluate(at, out.data());
    return out;
  };
  const Eigen::MatrixXd differences =
      terratraj::testing::centralDifferences(g, x, 1e-6, terratraj::testing::StepScale::kAbsolute);
  EXPECT_LT((differences - jacobian).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(IntervalBoundRows, NoneForShootingAndNamedAfterTheirLimit) {
  const models::VehicleLimits limits;
  const auto rowsOf = [&](TranscriptionScheme scheme, double final_time) {
    return IntervalBoundRows(scheme, uniformMesh(5), limits, final_time).count();
  };
  EXPECT_EQ(rowsOf(TranscriptionScheme::kMultipleShooting, 1.0), 0);
  EXPECT_EQ(rowsOf(TranscriptionScheme::kHermiteSimpson, 0.0), 0);
  EXPECT_EQ(rowsOf(TranscriptionScheme::kTrapezoidal, 1.0), 5 * 6);
  const IntervalBoundRows hs(TranscriptionScheme::kHermiteSimpson, uniformMesh(5), limits, 1.0);
  ASSERT_EQ(hs.count(), 5 * 2 * 6);
  EXPECT_STREQ(hs.name(0), "v_max_between_points");
  EXPECT_EQ(hs.point(0), 0);
  EXPECT_EQ(hs.point(1), 2);  // P2 of interval 0 is taken from its end node
  EXPECT_STREQ(hs.name(11), "kappa_max_between_points");
  EXPECT_EQ(hs.point(12), 2);  // interval 1 starts at node 1, point 2
}

// In a transcription: after the other rows, as many as the scheme has (none for shooting).
TEST(IntervalBoundRows, AreTheLastRowsOfACollocationNlp) {
  const terrain::ElevationMap map = bench::problem_sets::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem;
  problem.start = {2.0, 2.0, 0.0, 0.0, 0.0};
  problem.goal = {6.0, 3.0, 0.0, 0.0, 0.0};
  const TranscriptionModel model(vehicle, problem);
  for (TranscriptionScheme scheme :
       {TranscriptionScheme::kHermiteSimpson, TranscriptionScheme::kTrapezoidal,
        TranscriptionScheme::kMultipleShooting}) {
    TranscriptionLayout layout;
    layout.scheme = scheme;
    layout.mesh = uniformMesh(4);
    const int without = TranscriptionNlp(model, layout).constraintCount();
    layout.interval_bounds_final_time = 3.0;
    const TranscriptionNlp nlp(model, layout);
    const int expected = scheme == TranscriptionScheme::kHermiteSimpson ? 4 * 2 * 6
                         : scheme == TranscriptionScheme::kTrapezoidal  ? 4 * 6
                                                                        : 0;
    EXPECT_EQ(nlp.constraintCount() - without, expected) << transcriptionSchemeName(scheme);
    if (expected > 0) {
      EXPECT_STREQ(nlp.row(nlp.constraintCount() - 1).name, "kappa_max_between_points");
      EXPECT_STREQ(nlp.row(without).name, "v_max_between_points");
    }
  }
}

// The rows' final time: the guess's, capped at twice the straight drive (10 m at 1 m/s after
// 2 s of accelerating at 0.5 m/s^2: 24 s).
TEST(IntervalBoundRows, FinalTimeIsTheGuessesCappedAtTwiceTheStraightDrive) {
  BoundaryValueProblem problem;
  problem.start = {0.0, 0.0, 0.0, 0.0, 0.0};
  problem.goal = {6.0, 8.0, 0.0, 0.0, 0.0};
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  EXPECT_DOUBLE_EQ(intervalBoundsFinalTime(problem, 15.0), 15.0);
  EXPECT_DOUBLE_EQ(intervalBoundsFinalTime(problem, 84.0), 24.0);
}

}  // namespace
}  // namespace terratraj::ocp
