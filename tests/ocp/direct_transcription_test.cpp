// Direct transcription: derivatives against finite differences, and the optima it must reach
// (issue "Direct transcription"), each checked by an independent re-simulation.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "boundary_value_fixtures.hpp"
#include "common/finite_difference.hpp"
#include "dubins_length.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/ocp/transcription_solver.hpp"
#include "terratraj/terrain/clearance_map.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::ocp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A plane z = slope_x * x over 30 m x 10 m at 0.25 m.
terrain::ElevationMap rampMap(double slope_x) {
  terrain::GridGeometry geometry;
  geometry.rows = 40;
  geometry.cols = 120;
  geometry.cell = 0.25;
  terrain::ElevationMap map(geometry);
  for (int r = 0; r < geometry.rows; ++r) {
    for (int c = 0; c < geometry.cols; ++c) {
      map.elevation()(r, c) = static_cast<float>(slope_x * (c + 0.5) * geometry.cell);
    }
  }
  return map;
}

BoundaryValueProblem restToRest(double x0, double y0, double x1, double y1, double heading) {
  BoundaryValueProblem p;
  p.start = {x0, y0, heading, 0.0, 0.0};
  p.goal = {x1, y1, heading, 0.0, 0.0};
  p.limits = fixtures::looseLimits();
  return p;
}

TranscriptionGuess straightGuess(const BoundaryValueProblem& problem) {
  const Expected<TranscriptionGuess> guess = guessFromPath(
      {{problem.start.x, problem.start.y}, {problem.goal.x, problem.goal.y}}, problem);
  EXPECT_TRUE(guess.ok()) << guess.reason();
  return *guess;
}

// Variables near a guess, perturbed so that nothing sits on a kink.
Eigen::VectorXd perturbedVariables(const TranscriptionNlp& nlp, const TranscriptionGuess& guess,
                                   unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  Eigen::VectorXd x(nlp.variableCount());
  for (int p = 0; p < nlp.points(); ++p) {
    PointVector w = guess.at(guess.finalTime() * nlp.pointTimes()[static_cast<std::size_t>(p)]);
    for (int i = 0; i < kPointSize; ++i) w(i) += noise(random);
    w(3) = std::max(w(3), 0.2);
    x.segment<kPointSize>(kPointSize * p) = w;
  }
  x(nlp.finalTimeIndex()) = guess.finalTime() * 1.1;
  return x;
}

// Checks gradient, Jacobian and (collocation) Hessian against central differences.
void expectDerivativesMatch(TranscriptionNlp& nlp, const Eigen::VectorXd& x, double tolerance) {
  ASSERT_TRUE(nlp.evaluate(x.data())) << nlp.message();
  const Eigen::VectorXd gradient = nlp.gradient();
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(nlp.constraintCount(), nlp.variableCount());
  for (std::size_t i = 0; i < nlp.jacobianRows().size(); ++i) {
    jacobian(nlp.jacobianRows()[i], nlp.jacobianCols()[i]) +=
        nlp.jacobianValues()(static_cast<Eigen::Index>(i));
  }
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd lambda(nlp.constraintCount());
  for (int i = 0; i < lambda.size(); ++i) lambda(i) = unit(random);
  const double sigma = 0.7;
  const auto lagrangianGradient = [&](const Eigen::VectorXd& at) {
    EXPECT_TRUE(nlp.evaluate(at.data()));
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(nlp.constraintCount(), nlp.variableCount());
    for (std::size_t i = 0; i < nlp.jacobianRows().size(); ++i) {
      j(nlp.jacobianRows()[i], nlp.jacobianCols()[i]) +=
          nlp.jacobianValues()(static_cast<Eigen::Index>(i));
    }
    return Eigen::VectorXd(sigma * nlp.gradient() + j.transpose() * lambda);
  };
  // Row 0: the objective; rows 1..m: the constraints.
  const auto objective_and_constraints = [&](const Eigen::VectorXd& at) {
    EXPECT_TRUE(nlp.evaluate(at.data())) << nlp.message();
    Eigen::VectorXd out(1 + nlp.constraintCount());
    out << nlp.objective(), nlp.constraints();
    return out;
  };
  const Eigen::MatrixXd differences = terratraj::testing::centralDifferences(
      objective_and_constraints, x, 1e-6, terratraj::testing::StepScale::kRelative);
  double worst_gradient = 0.0, worst_jacobian = 0.0;
  for (int i = 0; i < nlp.variableCount(); ++i) {
    const double fd = differences(0, i);
    const Eigen::VectorXd column = differences.col(i).tail(nlp.constraintCount());
    worst_gradient = std::max(worst_gradient, std::abs(fd - gradient(i)) / (1.0 + std::abs(fd)));
    worst_jacobian = std::max(
        worst_jacobian,
        ((column - jacobian.col(i)).array().abs() / (1.0 + column.array().abs())).maxCoeff());
  }
  EXPECT_LT(worst_gradient, tolerance);
  EXPECT_LT(worst_jacobian, tolerance);
  if (!nlp.hasExactHessian()) return;
  const Eigen::MatrixXd hessian_fd = terratraj::testing::centralDifferences(
      lagrangianGradient, x, 1e-5, terratraj::testing::StepScale::kRelative);
  std::vector<double> values(nlp.hessianRows().size());
  ASSERT_TRUE(nlp.hessian(x.data(), sigma, lambda.data(), values.data()));
  Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(nlp.variableCount(), nlp.variableCount());
  for (std::size_t i = 0; i < values.size(); ++i) {
    hessian(nlp.hessianRows()[i], nlp.hessianCols()[i]) += values[i];
  }
  hessian = hessian.selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd symmetric_fd = 0.5 * (hessian_fd + hessian_fd.transpose());
  const double scale = 1.0 + symmetric_fd.cwiseAbs().maxCoeff();
  EXPECT_LT((hessian - symmetric_fd).cwiseAbs().maxCoeff() / scale, 100 * tolerance);
}

TEST(DirectTranscription, DerivativesMatchFiniteDifferencesOnRoughTerrain) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  // The suspension solved to 1e-12 m so that differences of 1e-6 m see its derivatives.
  models::RockerBogieSolverOptions tight;
  tight.tolerance = 1e-12;
  const models::RockerBogieAttitudeModel rocker(surface, {}, tight);
  const models::PointAttitudeModel point(surface);
  const terrain::ClearanceMap clearance(map);
  BoundaryValueProblem problem = fixtures::cruise(4.0, 5.0, 0.0, 9.0, 7.0, 0.5);
  problem.cost = {CostKind::kSlopeDwell, 2.0};
  const TranscriptionGuess guess = straightGuess(problem);
  TranscriptionModelOptions with_everything;
  with_everything.control_effort_weight = 0.1;
  with_everything.clearance = {&clearance, 0.1};
  for (const TranscriptionScheme scheme :
       {TranscriptionScheme::kTrapezoidal, TranscriptionScheme::kHermiteSimpson,
        TranscriptionScheme::kMultipleShooting}) {
    for (const models::TerrainFollowingModel* vehicle :
         {static_cast<const models::TerrainFollowingModel*>(&point),
          static_cast<const models::TerrainFollowingModel*>(&rocker)}) {
      SCOPED_TRACE(std::string(transcriptionSchemeName(scheme)) + " " + vehicle->name());
      const TranscriptionModel model(*vehicle, problem, with_everything);
      TranscriptionLayout layout;
      layout.scheme = scheme;
      layout.mesh = uniformMesh(4);
      layout.interval_bounds_final_time = 3.0;  // none for shooting
      TranscriptionNlp nlp(model, layout);
      // Shooting differentiates CVODES at rtol 1e-8: looser.
      expectDerivativesMatch(nlp, perturbedVariables(nlp, guess, 5),
                             scheme == TranscriptionScheme::kMultipleShooting ? 2e-4 : 2e-5);
    }
  }
}

// Hermite-Simpson with piecewise-linear controls: the control-linearity rows and their
// constant Jacobian against differences, and the rest unchanged.
TEST(DirectTranscription, LinearControlRowsMatchDifferences) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel point(surface);
  BoundaryValueProblem problem = fixtures::cruise(4.0, 5.0, 0.0, 9.0, 7.0, 0.5);
  const TranscriptionGuess guess = straightGuess(problem);
  const TranscriptionModel model(point, problem);
  TranscriptionLayout layout;
  layout.scheme = TranscriptionScheme::kHermiteSimpson;
  layout.mesh = uniformMesh(4);
  layout.linear_controls = true;
  TranscriptionNlp nlp(model, layout);
  EXPECT_EQ(nlp.defectRowCount() - nlp.controlRowStart(), 2 * 4);
  EXPECT_EQ(nlp.controlRowStart(), 2 * 4 * kStateSize);
  EXPECT_STREQ(nlp.row(nlp.controlRowStart() + 3).name, "control_linearity");
  EXPECT_EQ(nlp.row(nlp.controlRowStart() + 3).point, 1);
  const Eigen::VectorXd x = perturbedVariables(nlp, guess, 7);
  expectDerivativesMatch(nlp, x, 2e-5);
  ASSERT_TRUE(nlp.evaluate(x.data()));
  // Row 2 is interval 1's v': its midpoint (point 3) minus the mean of points 2 and 4.
  const double expected =
      x(kPointSize * 3 + 5) - 0.5 * (x(kPointSize * 2 + 5) + x(kPointSize * 4 + 5));
  EXPECT_NEAR(nlp.constraints()(nlp.controlRowStart() + 2), expected, 1e-15);
}

// Bang-bang rest to rest with piecewise-linear controls: the re-simulated acceleration stays
// within a_max between the points (quadratic controls overshoot a switch by up to 25 %).
TEST(DirectTranscription, LinearControlsHoldTheAccelerationBetweenPoints) {
  const terrain::ElevationMap map = fixtures::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = restToRest(5.0, 10.0, 9.0, 10.0, 0.0);
  problem.limits.a_max = 0.5;
  problem.limits.v_max = 2.0;
  DirectTranscriptionOptions options;
  options.intervals = 15;
  options.linear_controls = true;
  const TranscriptionSolution s =
      solveDirectTranscription(vehicle, problem, straightGuess(problem), options);
  ASSERT_EQ(s.result.status, SolveStatus::kConverged) << s.result.reason;
  EXPECT_NEAR(s.final_time / (2.0 * std::sqrt(4.0 / 0.5)), 1.0, 0.01);
  for (std::size_t k = 0; k + 2 < s.points.size(); k += 2) {
    EXPECT_NEAR(s.points[k + 1](5), 0.5 * (s.points[k](5) + s.points[k + 2](5)), 1e-7);
  }
  for (double t = 0.0; t <= s.final_time; t += s.final_time / 997.0) {
    EXPECT_LE(std::abs(s.controlsAt(t).x()), 0.5 + 1e-6) << t;
  }
  const TranscriptionModel model(vehicle, problem);
  const VerifiedTrajectory v = verifyTranscriptionSolution(model, s, &map);
  ASSERT_TRUE(v.ok) << v.message;
  EXPECT_LE(v.violation.amount, 1e-6) << v.violation.limit;
}

TEST(DirectTranscription, ShootingWithPiecewiseConstantControlsAndTheSegwayMatchDifferences) {
  const terrain::ElevationMap map = rampMap(-0.1);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = restToRest(3.0, 5.0, 9.0, 5.5, 0.0);
  TranscriptionModelOptions segway;
  segway.segway = SegwayConstraints{models::defaultSegwayLookups()};
  const TranscriptionModel model(vehicle, problem, segway);
  for (const TranscriptionScheme scheme :
       {TranscriptionScheme::kHermiteSimpson, TranscriptionScheme::kMultipleShooting}) {
    TranscriptionLayout layout;
    layout.scheme = scheme;
    layout.shooting_controls = ShootingControls::kPiecewiseConstant;
    layout.mesh = {0.0, 0.2, 0.5, 1.0};  // non-uniform
    TranscriptionNlp nlp(model, layout);
    expectDerivativesMatch(nlp, perturbedVariables(nlp, straightGuess(problem), 9), 2e-5);
  }
}

// Solves and re-simulates; the re-simulation must reach the goal.
struct Solved {
  TranscriptionSolution solution;
  VerifiedTrajectory verified;
};
Solved solveAndVerify(const models::TerrainFollowingModel& vehicle,
                      const BoundaryValueProblem& problem, const TranscriptionGuess& guess,
                      const DirectTranscriptionOptions& options, double goal_tolerance = 1e-3) {
  Solved out;
  out.solution = solveDirectTranscription(vehicle, problem, guess, options);
  EXPECT_EQ(out.solution.result.status, SolveStatus::kConverged)
      << out.solution.result.reason << " / " << out.solution.ipopt_status;
  const TranscriptionModel model(vehicle, problem, options.model);
  out.verified = verifyTranscriptionSolution(model, out.solution, nullptr);
  EXPECT_TRUE(out.verified.ok) << out.verified.message;
  EXPECT_LT(out.verified.terminal_error.head<2>().norm(), goal_tolerance);
  EXPECT_LT(std::abs(out.verified.terminal_error.z()), goal_tolerance);
  EXPECT_LT(out.verified.terminal_speed_error.cwiseAbs().maxCoeff(), 1e-6);
  std::printf(
      "  %s: t_f %.6f (re-simulated %.6f), cost %.6f, %d iterations, %.1f ms, worst %s %.3g\n",
      out.solution.result.method.c_str(), out.solution.final_time, out.verified.final_time,
      out.verified.cost, out.solution.result.iterations, out.solution.result.solve_time_ms,
      out.verified.violation.limit.c_str(), out.verified.violation.amount);
  return out;
}

TEST(DirectTranscription, RestToRestIsBangBangWithinHalfAPercent) {
  const terrain::ElevationMap map = fixtures::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const double d = 4.0, a_max = 0.5;
  for (const double v_max : {2.0, 1.0}) {  // not reached, reached
    for (const TranscriptionScheme scheme :
         {TranscriptionScheme::kHermiteSimpson, TranscriptionScheme::kTrapezoidal,
          TranscriptionScheme::kMultipleShooting}) {
      SCOPED_TRACE(std::string(transcriptionSchemeName(scheme)) + " v_max " +
                   std::to_string(v_max));
      BoundaryValueProblem problem = restToRest(5.0, 10.0, 5.0 + d, 10.0, 0.0);
      problem.limits.a_max = a_max;
      problem.limits.v_max = v_max;
      DirectTranscriptionOptions options;
      options.scheme = scheme;
      options.intervals = 50;
      // A little control effort picks one control on the singular arc at v_max (without it the
      // controls there ring between nodes: any alternating sequence has the same time).
      options.model.control_effort_weight = 1e-4;
      const Solved s = solveAndVerify(vehicle, problem, straightGuess(problem), options,
                                      scheme == TranscriptionScheme::kTrapezoidal ? 5e-3 : 1e-3);
      const double optimum =
          v_max * v_max / a_max >= d ? 2.0 * std::sqrt(d / a_max) : d / v_max + v_max / a_max;
      EXPECT_NEAR(s.solution.final_time / optimum, 1.0, 0.005);
      EXPECT_NEAR(s.verified.final_time / optimum, 1.0, 0.005);
      // Bang-bang at the nodes: |v'| = a_max, or v' ~ 0 at v = v_max (on that singular arc
      // collocation's controls ring between nodes, damped by the control effort), except in
      // the intervals around the switches.
      int bang = 0, nodes = 0;
      for (std::size_t p = 0; p < s.solution.points.size(); ++p) {
        if (scheme == TranscriptionScheme::kHermiteSimpson && p % 2 == 1) continue;
        const PointVector& w = s.solution.points[p];
        ++nodes;
        const bool saturated = std::abs(std::abs(w(5)) - a_max) < 1e-3 * a_max;
        const bool cruising = w(3) > 0.99 * v_max;
        if (saturated || cruising) ++bang;
      }
      EXPECT_GE(bang, nodes - 4);
      EXPECT_GT(s.solution.points[1](5), 0.99 * a_max);
      EXPECT_LT(s.solution.points[s.solution.points.size() - 2](5), -0.99 * a_max);
    }
  }
}

TEST(DirectTranscription, CurvatureBoundedConstantSpeedIsWithinTwoPercentOfDubins) {
  const terrain::ElevationMap map = fixtures::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  struct Case {
    double x1, y1, h1;
  };
  for (const Case c : {Case{9.0, 13.0, kPi / 2}, Case{12.0, 8.0, -kPi / 4}, Case{6.0, 12.0, kPi}}) {
    SCOPED_TRACE("goal " + std::to_string(c.x1) + ", " + std::to_string(c.y1));
    BoundaryValueProblem problem = fixtures::cruise(5.0, 10.0, 0.0, c.x1, c.y1, c.h1);
    problem.limits.v_max = 0.5;  // the start and goal speed: constant speed
    problem.limits.kappa_max = 1.0;
    problem.limits.sigma_max = 50.0;  // loose
    const double dubins = testing::dubinsLength(5.0, 10.0, 0.0, c.x1, c.y1, c.h1, 1.0);
    DirectTranscriptionOptions options;
    options.intervals = 80;
    options.model.control_effort_weight = 1e-4;
    const Solved loose = solveAndVerify(vehicle, problem, straightGuess(problem), options, 1e-2);
    const double ratio = loose.verified.final_time * 0.5 / dubins;
    EXPECT_GE(ratio, 1.0 - 1e-4);
    EXPECT_LE(ratio, 1.02);
    // Limits hold at the points; between them the interpolated yaw rate may pass kappa v.
    EXPECT_LT(loose.verified.violation.amount, 0.1) << loose.verified.violation.limit;
    // A tight curvature rate makes it longer.
    problem.limits.sigma_max = 0.5;
    const Solved tight = solveAndVerify(vehicle, problem, loose.solution.asGuess(), options, 1e-2);
    EXPECT_GT(tight.verified.final_time, loose.verified.final_time);
  }
}

TEST(DirectTranscription, SegwayPitchLimitIsActiveWhereItMustBe) {
  // Downhill (slope -0.1 rad along +x): the platform leans back when braking; uphill it leans
  // forward when accelerating. Limit 0.15 rad: braking downhill and accelerating uphill are
  // held to about 0.5 m/s^2, the other phases to a_max.
  for (const double slope : {-0.1, 0.1}) {
    SCOPED_TRACE("slope " + std::to_string(slope));
    const terrain::ElevationMap map = rampMap(std::tan(slope));
    const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
    const models::PointAttitudeModel vehicle(surface);
    BoundaryValueProblem problem = restToRest(3.0, 5.0, 11.0, 5.0, 0.0);
    problem.limits.a_max = 2.0;
    problem.limits.v_max = 3.0;
    problem.limits.pitch_max = 0.15;
    DirectTranscriptionOptions options;
    options.intervals = 60;
    options.model.control_effort_weight = 1e-4;
    options.model.segway = SegwayConstraints{models::defaultSegwayLookups()};
    const Solved s = solveAndVerify(vehicle, problem, straightGuess(problem), options);
    const TranscriptionModel model(vehicle, problem, options.model);
    models::AttitudeWorkspace workspace;
    PointEvaluation e = model.makeEvaluation();
    int active_braking = 0, active_accelerating = 0;
    for (const PointVector& w : s.solution.points) {
      ASSERT_EQ(model.evaluate(w, workspace, e), models::AttitudeStatus::kOk);
      EXPECT_LE(std::abs(e.platform_pitch) - problem.limits.pitch_max, 1e-6);
    }
    for (const ActiveConstraint& a : s.solution.active) {
      if (a.name != std::string("pitch_max")) continue;
      EXPECT_GT(a.multiplier, 0.0);
      const double v_dot = s.solution.points[static_cast<std::size_t>(a.point)](5);
      if (v_dot < -0.1) ++active_braking;
      if (v_dot > 0.1) ++active_accelerating;
    }
    if (slope < 0.0) {
      EXPECT_GT(active_braking, 5);
      EXPECT_EQ(active_accelerating, 0);
    } else {
      EXPECT_GT(active_accelerating, 5);
      EXPECT_EQ(active_braking, 0);
    }
  }
}

TEST(DirectTranscription, NeverWorseThanTheParametricOptimumBeyondDiscretisation) {
  const terrain::ElevationMap map = fixtures::singleHillMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  for (const double alpha : {0.0, 2.0}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    const BoundaryValueProblem problem = fixtures::singleHillProblem(alpha);
    // The parametric optimum to a tight stationarity (the default 0.1 stops wherever the
    // goal is reached first): both the comparison and the warm start need the optimum itself.
    BoundaryValueOptions tight;
    tight.criteria.lagrangian_gradient = 1e-5;
    const BoundaryValueSolution parametric = solveBoundaryValue(vehicle, problem, tight, &map);
    std::printf("  parametric: cost %.6f, %d iterations\n", parametric.verified.cost,
                parametric.solver.iterations);
    ASSERT_EQ(parametric.status, SolveStatus::kConverged) << parametric.reason;
    const Expected<TranscriptionGuess> guess = guessFromTrajectory(parametric.verified.trajectory);
    ASSERT_TRUE(guess.ok()) << guess.reason();
    DirectTranscriptionOptions options;
    options.intervals = 60;
    if (std::getenv("TT_PRINT") != nullptr) options.print_level = 5;
    const Solved s = solveAndVerify(vehicle, problem, *guess, options);
    // The discretisation error: the transcription's cost against its own re-simulation.
    const double discretisation = std::abs(s.solution.result.cost - s.verified.cost);
    EXPECT_LE(s.verified.cost, parametric.verified.cost + discretisation + 1e-6);
    EXPECT_LT(discretisation, 1e-3 * parametric.verified.cost);
  }
}

TEST(DirectTranscription, WarmStartsFromAnXyPathAndRefinesTheMesh) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::RockerBogieAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = restToRest(2.0, 2.0, 13.0, 9.0, 0.0);
  problem.goal.heading = kPi / 2;
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  problem.limits.kappa_max = 1.0;
  // A path with only x, y: an L with a corner.
  models::Trajectory path;
  path.has_column[static_cast<std::size_t>(models::TrajectoryColumn::kX)] = true;
  path.has_column[static_cast<std::size_t>(models::TrajectoryColumn::kY)] = true;
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(2, 2), Eigen::Vector2d(8, 2.5),
                                   Eigen::Vector2d(13, 4), Eigen::Vector2d(13, 9)}) {
    models::TrajectorySample sample = models::TrajectorySample::unknown();
    sample.x = p.x();
    sample.y = p.y();
    path.samples.push_back(sample);
  }
  const Expected<TranscriptionGuess> guess = guessFromCandidate(path, problem);
  ASSERT_TRUE(guess.ok()) << guess.reason();
  DirectTranscriptionOptions options;
  options.intervals = 12;
  options.model.control_effort_weight = 1e-3;
  options.refinement.max_rounds = 3;
  options.refinement.tolerance = 1e-3;
  const Solved s = solveAndVerify(vehicle, problem, *guess, options, 2e-2);
  ASSERT_GE(s.solution.refinement.size(), 2u);
  EXPECT_GT(s.solution.refinement.back().intervals, 12);
  EXPECT_LT(s.solution.refinement.back().max_interval_error,
            s.solution.refinement.front().max_interval_error);
  // Limits hold at the points; between them the interpolated yaw rate may pass kappa v.
  EXPECT_LT(s.verified.violation.amount, 0.25) << s.verified.violation.limit;
}

// From a converged solution put on a mesh twice as fine (what a verification round does), the
// warm barrier (monotone from a small mu) reaches the optimum Ipopt's adaptive one reaches.
// (Its iterations are compared where it pays, on planner candidates: CandidateRefiner tests.)
TEST(DirectTranscription, TheWarmBarrierReachesTheAdaptiveOptimumFromASolution) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = restToRest(2.0, 2.0, 14.0, 10.0, 0.0);
  problem.goal.heading = kPi / 2;
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  problem.limits.kappa_max = 1.0;
  problem.limits.sigma_max = 2.0;
  DirectTranscriptionOptions options;
  options.intervals = 25;
  options.linear_controls = true;
  options.model.control_effort_weight = 1e-3;
  const TranscriptionSolution coarse =
      solveDirectTranscription(vehicle, problem, straightGuess(problem), options);
  ASSERT_EQ(coarse.result.status, SolveStatus::kConverged) << coarse.result.reason;
  options.intervals = 50;
  const TranscriptionSolution adaptive =
      solveDirectTranscription(vehicle, problem, coarse.asGuess(), options);
  options.barrier = TranscriptionBarrier::kWarm;
  const TranscriptionSolution warm =
      solveDirectTranscription(vehicle, problem, coarse.asGuess(), options);
  ASSERT_EQ(adaptive.result.status, SolveStatus::kConverged) << adaptive.result.reason;
  ASSERT_EQ(warm.result.status, SolveStatus::kConverged) << warm.result.reason;
  EXPECT_NEAR(warm.final_time, adaptive.final_time, 1e-4 * adaptive.final_time);
  EXPECT_LT(warm.final_time, coarse.final_time);  // the finer mesh's optimum, not the guess
  RecordProperty("iterations_adaptive", adaptive.result.iterations);
  RecordProperty("iterations_warm", warm.result.iterations);
}

TEST(DirectTranscription, KeepsItsClearanceFromLethalCells) {
  // Flat 20 m x 20 m with a lethal block across the straight line from (3, 10) to (17, 10).
  terrain::ElevationMap map = fixtures::flatMap();
  terrain::GridLayer& lethal = map.addLayer("lethal");
  for (int r = 34; r < 46; ++r) {
    for (int c = 36; c < 44; ++c) lethal(r, c) = 1.0f;  // x 9..11 m, y 8.5..11.5 m
  }
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  const terrain::ClearanceMap clearance(map);
  BoundaryValueProblem problem = restToRest(3.0, 10.0, 17.0, 10.0, 0.0);
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  problem.limits.kappa_max = 1.0;
  // A candidate passing north of the block.
  const Expected<TranscriptionGuess> guess =
      guessFromPath({{3, 10}, {8, 12.5}, {12, 12.5}, {17, 10}}, problem);
  ASSERT_TRUE(guess.ok()) << guess.reason();
  DirectTranscriptionOptions options;
  options.intervals = 60;
  options.model.control_effort_weight = 1e-3;
  options.model.clearance = {&clearance, 0.5};
  const TranscriptionSolution s = solveDirectTranscription(vehicle, problem, *guess, options);
  ASSERT_EQ(s.result.status, SolveStatus::kConverged) << s.result.reason;
  const TranscriptionModel model(vehicle, problem, options.model);
  const VerifiedTrajectory verified = verifyTranscriptionSolution(model, s, &map);
  ASSERT_TRUE(verified.ok) << verified.message;
  EXPECT_NE(verified.violation.limit, "lethal");
  double closest = 1e9, north = -1e9;
  for (const PointVector& w : s.points) {
    closest = std::min(closest, clearance.at(w.head<2>())->distance);
    north = std::max(north, w(1));
  }
  EXPECT_GE(closest, 0.5 - 1e-6);  // at the points
  EXPECT_LT(closest, 0.51);        // and tight: the detour is no wider than needed
  EXPECT_GT(north, 11.5);          // still north of the block (its candidate's side)
  for (const models::TrajectorySample& sample : verified.trajectory.samples) {
    EXPECT_GT(clearance.at({sample.x, sample.y})->distance, 0.4);  // between the points too
  }
}

TEST(DirectTranscription, FailuresAreStatusesWithIpoptsReason) {
  const terrain::ElevationMap map = rampMap(std::tan(-0.1));
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  BoundaryValueProblem problem = restToRest(3.0, 5.0, 11.0, 5.0, 0.0);
  const TranscriptionGuess guess = straightGuess(problem);
  // A pitch limit below the slope: downhill the platform stays within it only while
  // accelerating at about g sin(slope), so the Segway cannot stop at the goal.
  DirectTranscriptionOptions segway;
  segway.intervals = 20;
  segway.max_iterations = 100;
  segway.model.segway = SegwayConstraints{models::defaultSegwayLookups()};
  BoundaryValueProblem steep = problem;
  steep.limits.pitch_max = 0.05;
  steep.limits.roll_max = 0.05;  // nor can it turn round and brake facing uphill
  const TranscriptionSolution infeasible = solveDirectTranscription(vehicle, steep, guess, segway);
  // Infeasible or diverged (the mapping), or out of iterations before Ipopt proves it
  // (L-BFGS, the Segway's default); never converged, always with a reason.
  EXPECT_TRUE(infeasible.result.status == SolveStatus::kInfeasible ||
              infeasible.result.status == SolveStatus::kDiverged ||
              infeasible.result.status == SolveStatus::kMaxIterations)
      << solveStatusName(infeasible.result.status) << ": " << infeasible.result.reason;
  EXPECT_FALSE(infeasible.result.reason.empty());
  EXPECT_FALSE(infeasible.ipopt_status.empty());
  // Inconsistent bounds.
  DirectTranscriptionOptions bounds;
  bounds.min_final_time = 5.0;
  bounds.max_final_time = 1.0;
  EXPECT_EQ(solveDirectTranscription(vehicle, problem, guess, bounds).result.status,
            SolveStatus::kError);
  // A goal beyond reach in the final-time bound.
  DirectTranscriptionOptions short_time;
  short_time.max_final_time = 1.0;
  short_time.intervals = 10;
  EXPECT_EQ(solveDirectTranscription(vehicle, problem, guess, short_time).result.status,
            SolveStatus::kInfeasible);
  // Too few degrees of freedom: one trapezoidal interval between fixed states.
  DirectTranscriptionOptions one;
  one.scheme = TranscriptionScheme::kTrapezoidal;
  one.intervals = 1;
  const TranscriptionSolution few = solveDirectTranscription(vehicle, problem, guess, one);
  EXPECT_EQ(few.result.status, SolveStatus::kInfeasible) << few.result.reason;
  // Exact Hessian asked of shooting; iteration limit; empty guess.
  DirectTranscriptionOptions shooting;
  shooting.scheme = TranscriptionScheme::kMultipleShooting;
  shooting.hessian = TranscriptionHessian::kExact;
  EXPECT_EQ(solveDirectTranscription(vehicle, problem, guess, shooting).result.status,
            SolveStatus::kError);
  DirectTranscriptionOptions capped;
  capped.max_iterations = 2;
  const TranscriptionSolution stopped = solveDirectTranscription(vehicle, problem, guess, capped);
  EXPECT_EQ(stopped.result.status, SolveStatus::kMaxIterations);
  EXPECT_EQ(stopped.ipopt_status, "Maximum_Iterations_Exceeded");
  EXPECT_EQ(solveDirectTranscription(vehicle, problem, TranscriptionGuess{}, {}).result.status,
            SolveStatus::kError);
  // Stopped by its time limit: not re-simulated (a wild iterate's re-simulation can take as
  // long again), the status saying why.
  TranscriptionSolveOptions limited;
  limited.time_limit_s = 1e-3;
  const VerifiedTranscription timed = solveTranscription(vehicle, problem, guess, limited);
  EXPECT_EQ(timed.status, SolveStatus::kMaxIterations) << timed.reason;
  EXPECT_TRUE(timed.solution.result.time_limit_reached);
  EXPECT_NE(timed.reason.find("time limit"), std::string::npos) << timed.reason;
  EXPECT_FALSE(timed.verified.ok);
  EXPECT_NE(timed.verified.message.find("not re-simulated"), std::string::npos);
  EXPECT_FALSE(stopped.result.time_limit_reached);
  // A stop request (SIGINT) ends it as its clock would, the reason saying so.
  std::atomic<bool> stop{true};
  TranscriptionSolveOptions interrupted;
  interrupted.stop = &stop;
  const VerifiedTranscription asked = solveTranscription(vehicle, problem, guess, interrupted);
  EXPECT_EQ(asked.status, SolveStatus::kMaxIterations) << asked.reason;
  EXPECT_TRUE(asked.time_limit_reached);
  EXPECT_NE(asked.reason.find("stopped on request"), std::string::npos) << asked.reason;
  EXPECT_LE(asked.iterations, 1);
  // Off the map.
  BoundaryValueProblem off = problem;
  off.goal.x = 40.0;
  const TranscriptionSolution off_map =
      solveDirectTranscription(vehicle, off, straightGuess(off), {});
  EXPECT_NE(off_map.result.status, SolveStatus::kConverged);
  EXPECT_NE(off_map.result.reason.find("cannot be placed"), std::string::npos)
      << off_map.result.reason;
}

}  // namespace
}  // namespace terratraj::ocp
