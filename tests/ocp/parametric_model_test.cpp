// The parametric formulation: control derivatives, terminal-map derivatives (sensitivities
// against finite differences), the flat initial guess, and Newton on flat ground.
#include <gtest/gtest.h>

#include <cmath>

#include "common/finite_difference.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/flat_ground_model.hpp"
#include "terratraj/ocp/initial_guess.hpp"
#include "terratraj/ocp/newton_solver.hpp"
#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::ocp {
namespace {

BoundaryValueProblem cruiseProblem(double gx, double gy, double gheading) {
  BoundaryValueProblem p;
  p.start = {2.0, 8.0, 0.0, 0.5, 0.0};
  p.goal = {2.0 + gx, 8.0 + gy, gheading, 0.5, 0.0};
  return p;
}

TEST(ParametricControls, DerivativesMatchFiniteDifferences) {
  ControlOrders orders{4, 3};
  VehicleState start{0, 0, 0, 0.2, 0.1}, goal{1, 1, 0, 0.4, -0.2};
  ParametricControls controls(start, goal, orders);
  Eigen::VectorXd q(6);
  q << 0.3, -0.2, 0.5, 0.7, -0.1, 3.0;
  controls.setParameters(q);
  const int n = controls.parameterCount();
  ASSERT_EQ(n, 6);
  double v, omega;
  controls.evaluate(3.0, v, omega, nullptr, nullptr);
  EXPECT_NEAR(v, 0.4, 1e-12);
  EXPECT_NEAR(omega, -0.2, 1e-12);
  controls.evaluate(0.0, v, omega, nullptr, nullptr);
  EXPECT_NEAR(v, 0.2, 1e-12);
  EXPECT_NEAR(omega, 0.1, 1e-12);
  for (double t : {0.3, 1.4, 2.9}) {
    Eigen::VectorXd dv(n), dw(n), dvd(n), dwd(n);
    controls.evaluate(t, v, omega, dv.data(), dw.data());
    const ControlRates r = controls.rates(t, dvd.data(), dwd.data());
    // Rates against time differences.
    const double h = 1e-6;
    const auto by_time = [&](const Eigen::VectorXd& at) {
      double v_at, omega_at;
      controls.evaluate(at(0), v_at, omega_at, nullptr, nullptr);
      return Eigen::Vector2d(v_at, omega_at);
    };
    EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
        Eigen::Vector2d(r.v_dot, r.omega_dot),
        terratraj::testing::centralDifferences(by_time, Eigen::VectorXd::Constant(1, t), h), 1e-6));
    // (v, omega, v', omega') by the parameters.
    const auto by_parameters = [&](const Eigen::VectorXd& at) {
      double v_at, omega_at;
      controls.setParameters(at);
      controls.evaluate(t, v_at, omega_at, nullptr, nullptr);
      const ControlRates rates_at = controls.rates(t, nullptr, nullptr);
      controls.setParameters(q);
      return Eigen::Vector4d(v_at, omega_at, rates_at.v_dot, rates_at.omega_dot);
    };
    Eigen::MatrixXd analytic(4, n);
    analytic << dv.transpose(), dw.transpose(), dvd.transpose(), dwd.transpose();
    EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
        analytic, terratraj::testing::centralDifferences(by_parameters, q, h), 1e-6));
  }
}

class RoughTerrain : public ::testing::Test {
 protected:
  void SetUp() override {
    terrain::GeneratorOptions options;
    options.kind = terrain::TerrainKind::kHills;
    options.rows = 96;
    options.cols = 96;
    options.cell = 0.25;
    options.seed = 3;
    map_ = terrain::generateTerrain(options);
    surface_ = std::make_unique<terrain::TerrainSurface>(map_, terrain::Interpolation::kBicubic);
  }
  terrain::ElevationMap map_;
  std::unique_ptr<terrain::TerrainSurface> surface_;
};

// Every (vehicle, cost) pair: discrete sensitivities of RK4 against central differences of the
// same discrete map (exact up to rounding), and CVODES's sensitivities against RK4's on a fine
// step (both approximate the true derivative; central differences of an adaptive integrator
// are noise at this level).
TEST_F(RoughTerrain, SensitivityDerivativesMatchFiniteDifferences) {
  // Contacts solved to 1e-11 m so that the central-difference reference is not noise.
  models::RockerBogieSolverOptions contact;
  contact.tolerance = 1e-11;
  const models::RockerBogieAttitudeModel rocker(*surface_, {}, contact);
  const models::PointAttitudeModel point(*surface_);
  for (const models::TerrainFollowingModel* vehicle :
       {static_cast<const models::TerrainFollowingModel*>(&point),
        static_cast<const models::TerrainFollowingModel*>(&rocker)}) {
    for (CostKind kind : {CostKind::kTime, CostKind::kSlopeDwell}) {
      SCOPED_TRACE(std::string(vehicle->name()) + (kind == CostKind::kTime ? " time" : " dwell"));
      BoundaryValueProblem problem = cruiseProblem(4.0, 1.0, 0.3);
      problem.cost = {kind, 1.5};
      problem.orders.speed = 2;
      ParametricModelOptions rk4_options;
      rk4_options.integrator.method = models::IntegrationMethod::kRk4;
      rk4_options.integrator.step = 0.002;
      ParametricTrajectoryModel rk4(*vehicle, problem, rk4_options);
      ParametricModelOptions cvodes_options;
      cvodes_options.integrator.relative_tolerance = 1e-10;
      cvodes_options.integrator.absolute_tolerance = 1e-12;
      ParametricTrajectoryModel cvodes(*vehicle, problem, cvodes_options);
      Eigen::VectorXd q(5);
      q << 0.1, -0.2, 0.1, 0.05, 9.0;
      ParametricEvaluation discrete, adaptive;
      ASSERT_TRUE(rk4.evaluate(q, DerivativeMode::kSensitivity, discrete)) << discrete.message;
      ASSERT_TRUE(cvodes.evaluate(q, DerivativeMode::kSensitivity, adaptive)) << adaptive.message;
      // Rows: the terminal state (3), then the cost.
      const auto state_and_cost = [&](const Eigen::VectorXd& at) {
        ParametricEvaluation e;
        EXPECT_TRUE(rk4.evaluate(at, DerivativeMode::kNone, e)) << e.message;
        Eigen::Vector4d out;
        out << e.terminal_state, e.cost;
        return out;
      };
      const Eigen::MatrixXd differences =
          terratraj::testing::centralDifferences(state_and_cost, q, 1e-5);
      for (int k = 0; k < q.size(); ++k) {
        const Eigen::Vector3d dc = differences.col(k).head<3>();
        const double dj = differences(3, k);
        const double scale = std::max(1.0, dc.norm());
        // t_f also stretches RK4's steps, which the continuous-time t_f column leaves out:
        // there the discrete map differs by the discretisation error.
        const double exact = k == rk4.finalTimeIndex() ? 1e-4 : 1e-6;
        EXPECT_LT((discrete.jacobian.col(k) - dc).norm(), exact * scale) << "column " << k;
        EXPECT_NEAR(discrete.gradient(k), dj, std::max(exact, 2e-5) * std::max(1.0, std::abs(dj)))
            << k;
        EXPECT_LT((adaptive.jacobian.col(k) - dc).norm(), 1e-4 * scale) << "column " << k;
        EXPECT_NEAR(adaptive.gradient(k), dj, 1e-4 * std::max(1.0, std::abs(dj))) << k;
      }
    }
  }
}

TEST(FlatGround, FanOfFortyFiveGoalsConverges) {
  terrain::GeneratorOptions options;
  options.kind = terrain::TerrainKind::kFlat;
  options.rows = 80;
  options.cols = 80;
  const terrain::ElevationMap map = terrain::generateTerrain(options);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBilinear);
  const models::PointAttitudeModel vehicle(surface);
  int converged = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 5; ++j) {
      const double angle = (-40.0 + 10.0 * i) * M_PI / 180.0;
      const double heading = (-60.0 + 30.0 * j) * M_PI / 180.0;
      BoundaryValueProblem problem;
      problem.start = {3.0, 10.0, 0.0, 0.5, 0.0};
      problem.goal = {3.0 + 5.0 * std::cos(angle), 10.0 + 5.0 * std::sin(angle), heading, 0.5, 0.0};
      const InitialGuess guess = flatInitialGuess(problem, surface);
      ASSERT_TRUE(guess.ok) << i << "," << j << " " << guess.reason;
      ParametricTrajectoryModel model(vehicle, problem);
      NewtonStart start{guess.q, guess.lambda, guess.hessian};
      const SolveResult result = solveNewton(model, start, NewtonOptions{}, "newton");
      if (result.status == SolveStatus::kConverged) ++converged;
      EXPECT_EQ(result.status, SolveStatus::kConverged) << i << "," << j << " " << result.reason;
      EXPECT_LT(result.terminal_error.head<2>().norm(), 1e-3);
      EXPECT_LT(std::abs(result.terminal_error.z()), 1e-3);
    }
  }
  EXPECT_EQ(converged, 45);
}

}  // namespace
}  // namespace terratraj::ocp
