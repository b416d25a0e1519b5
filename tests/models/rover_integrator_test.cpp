#include "terratraj/models/rover_integrator.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "common/finite_difference.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::models {
namespace {

using terrain::ElevationMap;
using terrain::Interpolation;
using terrain::TerrainSurface;

ElevationMap generated(terrain::TerrainKind kind, int size = 160) {
  terrain::GeneratorOptions options;
  options.kind = kind;
  options.rows = options.cols = size;
  options.cell = 0.25;
  options.seed = 9;
  return terrain::generateTerrain(options);
}

Eigen::Vector3d integrateTo(const RoverKinematics& kinematics, IntegratorOptions options,
                            const Eigen::Vector3d& start, const ControlProfile& controls,
                            double duration) {
  RoverIntegrator integrator(kinematics, options);
  IntegrationResult result;
  integrator.integrate(start, controls, duration, {}, result);
  EXPECT_EQ(result.status, IntegrationStatus::kOk) << result.message;
  return result.final_state;
}

IntegratorOptions cvodes(double tolerance) {
  IntegratorOptions options;
  options.method = IntegrationMethod::kCvodes;
  options.relative_tolerance = tolerance;
  options.absolute_tolerance = tolerance;
  return options;
}

IntegratorOptions fixedStep(IntegrationMethod method, double step) {
  IntegratorOptions options;
  options.method = method;
  options.step = step;
  return options;
}

TEST(RoverKinematics, RatesAndJacobiansMatchFiniteDifferences) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills, 96);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  RockerBogieSolverOptions precise;
  precise.tolerance = 1e-12;
  const RockerBogieAttitudeModel model(surface, RockerBogieGeometry{}, precise);
  const RoverKinematics kinematics(model);
  AttitudeWorkspace workspace;
  const Eigen::Matrix<double, 5, 1> state =
      (Eigen::Matrix<double, 5, 1>() << 11.3, 9.7, 0.8, 0.7, 0.25).finished();
  const Eigen::Vector2d control(0.3, -0.1);
  RoverStateSpaceRates rates;
  ASSERT_EQ(kinematics.stateSpaceRates(state, control, workspace, rates), AttitudeStatus::kOk);
  // The reduced rates: x' = v cos(heading) cos(pitch), ...
  const double pitch = rates.attitude.attitude.pitch, roll = rates.attitude.attitude.roll;
  EXPECT_NEAR(rates.rate(0), 0.7 * std::cos(0.8) * std::cos(pitch), 1e-14);
  EXPECT_NEAR(rates.rate(2), 0.25 * std::cos(roll) / std::cos(pitch), 1e-14);
  const double h = 1e-6;
  const auto by_state = [&](const Eigen::VectorXd& at) {
    RoverStateSpaceRates a;
    AttitudeWorkspace cold;
    EXPECT_EQ(kinematics.stateSpaceRates(at, control, cold, a), AttitudeStatus::kOk);
    return Eigen::VectorXd(a.rate);
  };
  EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
      rates.d_state, terratraj::testing::centralDifferences(by_state, state, h), 1e-6));
  const auto by_control = [&](const Eigen::VectorXd& at) {
    RoverStateSpaceRates a;
    EXPECT_EQ(kinematics.stateSpaceRates(state, Eigen::Vector2d(at), workspace, a),
              AttitudeStatus::kOk);
    return Eigen::VectorXd(a.rate);
  };
  EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
      rates.d_control, terratraj::testing::centralDifferences(by_control, control, h), 1e-8));
}

TEST(RoverIntegrator, ConstantControlsOnFlatGroundGiveTheExactArc) {
  const ElevationMap map = generated(terrain::TerrainKind::kFlat, 256);
  const TerrainSurface surface(map, Interpolation::kBilinear);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  const double v = 1.0, omega = 0.3, duration = 10.0, heading0 = 0.4;
  const Eigen::Vector3d start(32.0, 30.0, heading0);
  const Eigen::Vector3d exact(
      start.x() + v / omega * (std::sin(heading0 + omega * duration) - std::sin(heading0)),
      start.y() - v / omega * (std::cos(heading0 + omega * duration) - std::cos(heading0)),
      heading0 + omega * duration);
  const PolynomialControls controls({v}, {omega});
  EXPECT_LT((integrateTo(kinematics, cvodes(1e-13), start, controls, duration) - exact).norm(),
            1e-9);
  EXPECT_LT((integrateTo(kinematics, fixedStep(IntegrationMethod::kRk4, 1e-3), start, controls,
                         duration) -
             exact)
                .norm(),
            1e-9);
  // Explicit Euler is first order: 1e-4 s steps leave an error of order 1e-4 m over 10 s.
  const double euler_error = (integrateTo(kinematics, fixedStep(IntegrationMethod::kEuler, 1e-4),
                                          start, controls, duration) -
                              exact)
                                 .norm();
  EXPECT_LT(euler_error, 1e-3);
  EXPECT_GT(euler_error, 1e-6);
}

TEST(RoverIntegrator, TheThreeMethodsAgreeOnRoughTerrain) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const RockerBogieAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  const PolynomialControls controls({0.5, 0.05}, {0.2, -0.03});
  const Eigen::Vector3d start(8.0, 18.0, 0.3);
  const Eigen::Vector3d reference = integrateTo(kinematics, cvodes(1e-11), start, controls, 8.0);
  const Eigen::Vector3d cvodes_default =
      integrateTo(kinematics, IntegratorOptions{}, start, controls, 8.0);
  const Eigen::Vector3d rk4 =
      integrateTo(kinematics, fixedStep(IntegrationMethod::kRk4, 0.01), start, controls, 8.0);
  const Eigen::Vector3d euler =
      integrateTo(kinematics, fixedStep(IntegrationMethod::kEuler, 0.001), start, controls, 8.0);
  EXPECT_LT((cvodes_default - reference).norm(), 1e-6);  // rtol 1e-8
  EXPECT_LT((rk4 - reference).norm(), 1e-5);
  EXPECT_LT((euler - reference).norm(), 1e-2);
  EXPECT_GT((reference.head<2>() - start.head<2>()).norm(), 3.0);  // it really went somewhere
}

// Central differences of the final state by each control parameter.
Eigen::MatrixXd finiteDifferenceSensitivity(const RoverKinematics& kinematics,
                                            const IntegratorOptions& options,
                                            const Eigen::Vector3d& start,
                                            const PolynomialControls& controls, double duration,
                                            double h) {
  IntegratorOptions plain = options;
  plain.sensitivities = false;
  const auto final_state = [&](const Eigen::VectorXd& q) {
    PolynomialControls at = controls;
    at.setParameters(q);
    return Eigen::VectorXd(integrateTo(kinematics, plain, start, at, duration));
  };
  return terratraj::testing::centralDifferences(final_state, controls.parameters(), h);
}

TEST(RoverIntegrator, SensitivitiesMatchFiniteDifferences) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel point(surface);
  RockerBogieSolverOptions precise;
  precise.tolerance = 1e-12;
  const RockerBogieAttitudeModel rocker_bogie(surface, RockerBogieGeometry{}, precise);
  const PolynomialControls controls({0.5, 0.05, -0.002}, {0.2, -0.03, 0.001});
  const Eigen::Vector3d start(8.0, 18.0, 0.3);
  for (const TerrainFollowingModel* model :
       std::initializer_list<const TerrainFollowingModel*>{&point, &rocker_bogie}) {
    const RoverKinematics kinematics(*model);
    IntegratorOptions controlled = cvodes(1e-11);
    controlled.sensitivity_error_control = true;
    for (IntegratorOptions options :
         {cvodes(1e-11), controlled, fixedStep(IntegrationMethod::kRk4, 0.01),
          fixedStep(IntegrationMethod::kEuler, 0.01)}) {
      options.sensitivities = true;
      RoverIntegrator integrator(kinematics, options);
      IntegrationResult result;
      integrator.integrate(start, controls, 6.0, {}, result);
      ASSERT_EQ(result.status, IntegrationStatus::kOk) << result.message;
      const Eigen::MatrixXd fd =
          finiteDifferenceSensitivity(kinematics, options, start, controls, 6.0, 1e-5);
      const double relative = (result.sensitivity - fd).norm() / fd.norm();
      EXPECT_LT(relative, 1e-5) << model->name() << " " << integrationMethodName(options.method)
                                << (options.sensitivity_error_control ? " (error control)" : "")
                                << "\nsensitivity\n"
                                << result.sensitivity << "\nfd\n"
                                << fd;
    }
  }
}

// A smooth running cost that depends on the state and both inputs.
class MixedIntegrand final : public RunningIntegrand {
 public:
  double evaluate(double /*t*/, const RoverRates& /*rates*/, double v, double omega,
                  Eigen::Vector3d* d_state, Eigen::Vector2d* d_input) const override {
    if (d_state != nullptr) d_state->setZero();
    if (d_input != nullptr) *d_input << 2 * v + omega * std::cos(v), std::sin(v);
    return v * v + omega * std::sin(v);
  }
};

// A cost that depends on the state: its sensitivities go through S(t).
class StateIntegrand final : public RunningIntegrand {
 public:
  double evaluate(double /*t*/, const RoverRates& rates, double v, double /*omega*/,
                  Eigen::Vector3d* d_state, Eigen::Vector2d* d_input) const override {
    // pitch^2 + roll^2 of the terrain under the vehicle, times the speed.
    const AttitudeResult& a = rates.attitude;
    const double s = a.attitude.pitch * a.attitude.pitch + a.attitude.roll * a.attitude.roll;
    if (d_state != nullptr) {
      *d_state =
          v * 2 *
          (a.attitude.pitch * a.jacobian.row(2) + a.attitude.roll * a.jacobian.row(1)).transpose();
    }
    if (d_input != nullptr) *d_input << s, 0.0;
    return v * s;
  }
};

// The running integral and its sensitivities: central differences, RK4, and the same numbers
// whatever the integrator did before (CVODES 6.4's quadrature sensitivities, used until they
// were found to read uninitialised memory, gave a history- and heap-dependent gradient).
TEST(RoverIntegrator, IntegralSensitivitiesMatchFiniteDifferencesWhateverCameBefore) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel point(surface);
  const RoverKinematics kinematics(point);
  const PolynomialControls controls({0.5, 0.05, -0.002}, {0.2, -0.03, 0.001});
  const PolynomialControls other({0.8, -0.04}, {-0.1, 0.02, 0.002});
  const Eigen::Vector3d start(8.0, 18.0, 0.3);
  const MixedIntegrand mixed;
  const StateIntegrand state;
  for (const RunningIntegrand* integrand :
       std::initializer_list<const RunningIntegrand*>{&mixed, &state}) {
    SCOPED_TRACE(integrand == &mixed ? "inputs only" : "state");
    IntegratorOptions options = cvodes(1e-11);
    options.sensitivities = true;
    RoverIntegrator integrator(kinematics, options);
    IntegrationResult warm_up, first, again;
    integrator.integrate(start, other, 9.0, {}, warm_up, integrand);
    integrator.integrate(start, controls, 6.0, {}, first, integrand);
    integrator.integrate(start, other, 3.0, {}, warm_up, integrand);
    integrator.integrate(start, controls, 6.0, {}, again, integrand);
    ASSERT_EQ(first.status, IntegrationStatus::kOk) << first.message;
    EXPECT_EQ(first.integral, again.integral);
    EXPECT_EQ(first.integral_sensitivity, again.integral_sensitivity);
    EXPECT_EQ(first.sensitivity, again.sensitivity);

    IntegratorOptions rk4 = fixedStep(IntegrationMethod::kRk4, 0.001);
    RoverIntegrator reference(kinematics, rk4);
    IntegrationResult fixed;
    reference.integrate(start, controls, 6.0, {}, fixed, integrand);
    EXPECT_NEAR(first.integral, fixed.integral, 1e-8 * std::max(1.0, std::abs(fixed.integral)));

    const Eigen::VectorXd q = controls.parameters();
    IntegratorOptions plain = options;
    plain.sensitivities = false;
    const auto integral = [&](const Eigen::VectorXd& at) {
      PolynomialControls perturbed_controls = controls;
      perturbed_controls.setParameters(at);
      RoverIntegrator fresh(kinematics, plain);
      IntegrationResult r;
      fresh.integrate(start, perturbed_controls, 6.0, {}, r, integrand);
      return Eigen::VectorXd::Constant(1, r.integral);
    };
    const Eigen::MatrixXd differences = terratraj::testing::centralDifferences(integral, q, 1e-5);
    for (Eigen::Index i = 0; i < q.size(); ++i) {
      const double fd = differences(0, i);
      // The state-dependent cost reads the attitude's Jacobian, only piecewise smooth on a
      // bicubic surface: there even RK4's exact discrete derivative and its own central
      // differences differ by 2.5e-5 (relative).
      const double tolerance = integrand == &mixed ? 1e-6 : 2e-4;
      EXPECT_NEAR(first.integral_sensitivity(i), fd, tolerance * std::max(1.0, std::abs(fd)))
          << "parameter " << i;
    }
  }
}

TEST(RoverIntegrator, SamplesAtRequestedTimes) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  const PolynomialControls controls({0.8}, {0.1});
  for (const IntegratorOptions& options :
       {cvodes(1e-10), fixedStep(IntegrationMethod::kRk4, 0.01)}) {
    RoverIntegrator integrator(kinematics, options);
    IntegrationResult result;
    const std::vector<double> times = uniformSampleTimes(5.0, 0.25);
    integrator.integrate({8.0, 18.0, 0.0}, controls, 5.0, times, result);
    ASSERT_EQ(result.status, IntegrationStatus::kOk);
    ASSERT_EQ(result.samples.samples.size(), 21u);
    EXPECT_DOUBLE_EQ(result.samples.samples.back().t, 5.0);
    EXPECT_NEAR(result.samples.samples.back().x, result.final_state.x(), 1e-12);
    EXPECT_DOUBLE_EQ(result.samples.samples[0].x, 8.0);
    EXPECT_NEAR(result.samples.samples[4].curvature, 0.1 / 0.8, 1e-12);
    EXPECT_TRUE(std::isfinite(result.samples.samples[7].pitch));
    // Dense samples: several inside the last step, the final one at the stop time (a sample
    // there once repeated the previous one).
    integrator.integrate({8.0, 18.0, 0.0}, controls, 5.0, uniformSampleTimes(5.0, 0.003), result);
    ASSERT_EQ(result.status, IntegrationStatus::kOk);
    EXPECT_NEAR(result.samples.samples.back().x, result.final_state.x(), 1e-12);
    EXPECT_NEAR(result.samples.samples.back().y, result.final_state.y(), 1e-12);
  }
}

// A deadline already past stops an integration of `duration` [s] with the reason, within 128
// steps; one an hour away lets a 5 s integration finish.
void expectStopsAtItsDeadline(const RoverKinematics& kinematics, IntegratorOptions options,
                              const PolynomialControls& controls, double duration) {
  options.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  IntegrationResult result;
  RoverIntegrator past(kinematics, options);
  past.integrate({8.0, 18.0, 0.0}, controls, duration, {}, result);
  EXPECT_EQ(result.status, IntegrationStatus::kSolverFailure);
  EXPECT_NE(result.message.find("time limit"), std::string::npos) << result.message;
  EXPECT_LT(result.steps, 128);
  options.deadline = std::chrono::steady_clock::now() + std::chrono::hours(1);
  RoverIntegrator later(kinematics, options);
  later.integrate({8.0, 18.0, 0.0}, controls, 5.0, {}, result);
  EXPECT_EQ(result.status, IntegrationStatus::kOk) << result.message;
}

// CVODES and the fixed-step schemes honour the deadline (every 64 steps): the flat-ground
// guess integrates iterates whose final time runs to hours at 0.1 s steps.
TEST(RoverIntegrator, StopsAtItsDeadline) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  expectStopsAtItsDeadline(kinematics, cvodes(1e-10), PolynomialControls({0.8}, {0.1}), 5.0);
  // Standing still, turning: on the map for as long as it integrates.
  expectStopsAtItsDeadline(kinematics, fixedStep(IntegrationMethod::kRk4, 0.1),
                           PolynomialControls({0.0}, {0.1}), 1e6);
}

// Beside no data the surface ends inside the map (the B-spline reads two cells around a point).
// CVODES takes a failed evaluation in its corrector as recoverable and shortens the step; where
// the solution itself drives off the surface it used to shrink it to 1e-14 s and grind through
// a million steps (a refinement on the gully). The minimum step ends the run at the edge.
TEST(RoverIntegrator, StopsAtTheEdgeOfTheSurfaceBesideNoData) {
  ElevationMap map = generated(terrain::TerrainKind::kHills, 64);
  for (int r = 0; r < map.geometry().rows; ++r) {
    for (int c = 0; c <= 9; ++c) map.elevation()(r, c) = std::nanf("");
  }
  const TerrainSurface surface(map, Interpolation::kCubicBSpline);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  const double edge = (9 + 2 + 0.5) * map.geometry().cell;  // u < 11 reads a no-data cell
  for (const double heading : {M_PI, M_PI - 0.6, M_PI + 0.3}) {
    SCOPED_TRACE(heading);
    RoverIntegrator integrator(kinematics, cvodes(1e-8));
    IntegrationResult result;
    integrator.integrate({8.0, 8.0, heading}, PolynomialControls({1.0}, {0.0}), 10.0,
                         uniformSampleTimes(10.0, 0.05), result);
    EXPECT_EQ(result.status, IntegrationStatus::kNoTerrain) << result.message;
    EXPECT_LT(result.steps, 2000);
    EXPECT_NEAR(result.final_state.x(), edge, 0.05);
  }
}

TEST(RoverIntegrator, FailuresAreStatusesWithReasons) {
  const ElevationMap map = generated(terrain::TerrainKind::kHills, 64);
  const TerrainSurface surface(map, Interpolation::kBicubic);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  const PolynomialControls west({1.0}, {0.0});
  for (const IntegratorOptions& options : {cvodes(1e-8), fixedStep(IntegrationMethod::kRk4, 0.01),
                                           fixedStep(IntegrationMethod::kEuler, 0.01)}) {
    RoverIntegrator integrator(kinematics, options);
    IntegrationResult result;
    integrator.integrate({2.0, 8.0, M_PI}, west, 10.0, {}, result);  // drives off the west edge
    EXPECT_EQ(result.status, IntegrationStatus::kNoTerrain)
        << integrationMethodName(options.method);
    EXPECT_GT(result.t_reached, 1.5);
    EXPECT_LT(result.t_reached, 2.1);
    EXPECT_GT(result.final_state.x(), -0.02);  // the last accepted step: at most one step out
    EXPECT_LT(result.final_state.x(), 0.5);
    integrator.integrate({2.0, 8.0, 0.0}, west, -1.0, {}, result);
    EXPECT_EQ(result.status, IntegrationStatus::kInvalidInput);
    integrator.integrate({2.0, 8.0, 0.0}, west, 1.0, {0.5, 0.2}, result);
    EXPECT_EQ(result.status, IntegrationStatus::kInvalidInput);
  }
  IntegratorOptions starved = cvodes(1e-10);
  starved.max_steps = 3;
  RoverIntegrator integrator(kinematics, starved);
  IntegrationResult result;
  integrator.integrate({2.0, 8.0, 0.0}, west, 5.0, {}, result);
  EXPECT_EQ(result.status, IntegrationStatus::kSolverFailure);
  EXPECT_THAT(result.message, ::testing::HasSubstr("CV_TOO_MUCH_WORK"));
  IntegratorOptions bad;
  bad.step = 0.0;
  EXPECT_THROW(RoverIntegrator(kinematics, bad), std::invalid_argument);
}

}  // namespace
}  // namespace terratraj::models
