#include "terratraj/ocp/initial_guess.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "terratraj/ocp/flat_ground_model.hpp"
#include "terratraj/ocp/newton_solver.hpp"
#include "terratraj/ocp/parametric_trajectory_model.hpp"

namespace terratraj::ocp {
namespace {

constexpr int kFitSamples = 21;

// Least-squares fit of the free coefficients of p(tau) = sum_k c_k tau^k (c_K closed by
// delta) to target(tau) - p0.
template <typename Target>
Eigen::VectorXd fitClosedPolynomial(int order, double delta, Target target) {
  const int free = order - 1;
  if (free == 0) return Eigen::VectorXd();
  Eigen::MatrixXd m(kFitSamples, free);
  Eigen::VectorXd b(kFitSamples);
  for (int i = 0; i < kFitSamples; ++i) {
    const double tau = static_cast<double>(i) / (kFitSamples - 1);
    const double top = std::pow(tau, order);
    for (int k = 1; k <= free; ++k) m(i, k - 1) = std::pow(tau, k) - top;
    b(i) = target(tau) - delta * top;
  }
  return m.colPivHouseholderQr().solve(b);
}

// Flat-ground integration: RK4 with steps of 0.1 s (the flat map is smooth; this is a seed).
ParametricModelOptions flatOptions(const GuessDeadline& deadline) {
  ParametricModelOptions options;
  options.integrator.method = models::IntegrationMethod::kRk4;
  options.integrator.step = 0.1;
  options.integrator.deadline = deadline;
  return options;
}

}  // namespace

Eigen::VectorXd heuristicGuess(const BoundaryValueProblem& problem) {
  const VehicleState& s = problem.start;
  const VehicleState& g = problem.goal;
  const double c = std::cos(s.heading), sn = std::sin(s.heading);
  const double dx = c * (g.x - s.x) + sn * (g.y - s.y);
  const double dy = -sn * (g.x - s.x) + c * (g.y - s.y);
  const double distance = std::hypot(dx, dy);
  const double bearing = std::atan2(dy, dx);
  const double turn = wrapAngle(g.heading - s.heading);
  // Nagy & Kelly's arc-length estimate, with the heading changes at both ends.
  const double length =
      distance * (1.0 + (bearing * bearing + (turn - bearing) * (turn - bearing)) / 5.0) + 0.1;

  const ParametricControls layout(s, g, problem.orders);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(layout.parameterCount());
  const int speed_order = problem.orders.speed;
  const double cruise = std::max({0.7 * problem.limits.v_max, s.v, g.v, 1e-3});
  // Speed: rise to cruise over the first quarter, hold, fall over the last quarter.
  const auto speed_target = [&](double tau) {
    if (tau < 0.25) return s.v + (cruise - s.v) * tau / 0.25;
    if (tau > 0.75) return g.v + (cruise - g.v) * (1.0 - tau) / 0.25;
    return cruise;
  };
  const Eigen::VectorXd speed = fitClosedPolynomial(
      speed_order, g.v - s.v, [&](double tau) { return speed_target(tau) - s.v; });
  q.segment(layout.speedIndex(), speed.size()) = speed;
  ParametricControls fitted(s, g, problem.orders);
  Eigen::VectorXd probe = q;
  probe(layout.finalTimeIndex()) = 1.0;
  fitted.setParameters(probe);
  double mean_speed = 0.0;
  for (int i = 0; i < kFitSamples; ++i) {
    double v = 0.0, omega = 0.0;
    fitted.evaluate(static_cast<double>(i) / (kFitSamples - 1), v, omega, nullptr, nullptr);
    mean_speed += std::abs(v) / kFitSamples;
  }
  const double tf = length / std::max(mean_speed, 1e-3);
  // Yaw rate: turn toward the goal, then align with its heading: omega = turn / t_f +
  // A (1 - 2 tau), with A such that the mean heading (turn / 2 + A t_f / 6) is the bearing.
  const double a = 6.0 * (bearing - 0.5 * turn) / tf;
  const Eigen::VectorXd yaw =
      fitClosedPolynomial(problem.orders.yaw_rate, g.omega - s.omega,
                          [&](double tau) { return turn / tf + a * (1.0 - 2.0 * tau) - s.omega; });
  q.head(yaw.size()) = yaw;
  q(layout.finalTimeIndex()) = tf;
  return q;
}

InitialGuess flatInitialGuess(const BoundaryValueProblem& problem,
                              const terrain::TerrainSurface& surface,
                              const GuessDeadline& deadline) {
  return flatInitialGuess(problem, surface, heuristicGuess(problem), deadline);
}

Eigen::VectorXd fitParametricControls(const BoundaryValueProblem& problem,
                                      const std::vector<double>& t, const std::vector<double>& v,
                                      const std::vector<double>& omega, double path_length) {
  const int yaw_order = problem.orders.yaw_rate, speed_order = problem.orders.speed;
  const std::size_t n = t.size();
  const double tf = t.back() - t.front();
  // One least-squares fit per control: value(tau) - value_0 - delta tau^K
  // = sum_{k<K} c_k (tau^k - tau^K).
  const auto fit = [&](const std::vector<double>& values, int order, double start, double end) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(std::max(order - 1, 0));
    if (order <= 1) return c;
    Eigen::MatrixXd a(n, order - 1);
    Eigen::VectorXd b(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double tau = (t[i] - t.front()) / tf;
      const double top = std::pow(tau, order);
      for (int k = 1; k < order; ++k) a(i, k - 1) = std::pow(tau, k) - top;
      b(i) = values[i] - start - (end - start) * top;
    }
    c = a.colPivHouseholderQr().solve(b);
    return c;
  };
  const Eigen::VectorXd w = fit(omega, yaw_order, problem.start.omega, problem.goal.omega);
  const Eigen::VectorXd s = fit(v, speed_order, problem.start.v, problem.goal.v);
  // The mean of the fitted speed over tau: v_0 + sum_k s_k / (k + 1), s_M closing the sum.
  double mean = problem.start.v;
  double closing = problem.goal.v - problem.start.v;
  for (int k = 1; k < speed_order; ++k) {
    mean += s(k - 1) / (k + 1.0);
    closing -= s(k - 1);
  }
  mean += closing / (speed_order + 1.0);
  Eigen::VectorXd q(w.size() + s.size() + 1);
  q << w, s, (mean > 1e-3 && path_length > 0.0 ? path_length / mean : tf);
  return q;
}

InitialGuess flatInitialGuess(const BoundaryValueProblem& problem,
                              const terrain::TerrainSurface& surface,
                              const Eigen::VectorXd& start_q, const GuessDeadline& deadline) {
  InitialGuess guess;
  const FlatGroundModel flat(surface);
  BoundaryValueProblem flat_problem = problem;
  flat_problem.cost.kind = CostKind::kTime;  // no slope to dwell on
  ParametricTrajectoryModel model(flat, flat_problem, flatOptions(deadline));
  const int itf = model.finalTimeIndex();
  Eigen::VectorXd q = start_q;
  guess.q = q;

  // Fully constrained: Gauss-Newton with minimum-norm (Levenberg) steps on c(q) = 0.
  ParametricEvaluation at, trial;
  bool solved = false;
  double mu = 1e-6;
  const auto past_deadline = [&] {
    return deadline && std::chrono::steady_clock::now() > *deadline;
  };
  if (model.evaluate(q, DerivativeMode::kSensitivity, at)) {
    for (int iteration = 0; iteration < 60 && !solved && !past_deadline(); ++iteration) {
      if (at.terminal_error.norm() < 1e-9) {
        solved = true;
        break;
      }
      const Eigen::MatrixXd& a = at.jacobian;
      bool improved = false;
      for (int tries = 0; tries < 30 && !improved && !past_deadline(); ++tries, mu *= 10.0) {
        const Eigen::Matrix3d aat = a * a.transpose() + mu * Eigen::Matrix3d::Identity();
        Eigen::VectorXd d = -a.transpose() * aat.ldlt().solve(at.terminal_error);
        if (d(itf) < 0.0) d *= std::min(1.0, 0.5 * q(itf) / -d(itf));
        const Eigen::VectorXd q_next = q + d;
        if (model.evaluate(q_next, DerivativeMode::kSensitivity, trial) &&
            trial.terminal_error.norm() < at.terminal_error.norm()) {
          q = q_next;
          std::swap(at, trial);
          improved = true;
          mu = std::max(1e-9, mu / 100.0);
        }
      }
      if (!improved) break;
    }
    solved = solved || at.terminal_error.norm() < 1e-6;
  }
  guess.integrations = model.integrations();
  if (!solved && past_deadline()) {
    guess.reason = "time limit reached while fitting the flat-ground initial guess";
    return guess;
  }
  if (!solved) {
    guess.reason =
        "no flat-ground trajectory of this polynomial form reaches the goal from "
        "the heuristic guess (yaw-rate order " +
        std::to_string(problem.orders.yaw_rate) + ", speed order " +
        std::to_string(problem.orders.speed) + ")";
    return guess;
  }
  guess.ok = true;
  guess.q = q;
  guess.lambda = leastSquaresMultipliers(at.jacobian, at.gradient);

  // The flat-ground optimum (Newton with finite-difference Hessians: the flat map is cheap).
  NewtonOptions options;
  options.hessian = HessianApproximation::kFiniteDifference;
  options.hessian_step = 1e-6;
  options.max_iterations = 30;
  options.criteria = {1e-5, 1e-5, 1e-4};
  if (deadline) {
    options.time_limit_s = std::max(
        0.0, std::chrono::duration<double>(*deadline - std::chrono::steady_clock::now()).count());
  }
  NewtonStart start{q, guess.lambda, Eigen::MatrixXd()};
  const SolveResult optimum = solveNewton(model, start, options, "flat");
  guess.integrations = model.integrations();
  if (optimum.status == SolveStatus::kConverged) {
    guess.q = optimum.q;
    guess.lambda = optimum.lambda;
    guess.flat_optimum = true;
    if (!model.lagrangianHessian(guess.q, guess.lambda, DerivativeMode::kSensitivity, 1e-6,
                                 guess.hessian)) {
      guess.hessian.resize(0, 0);
    }
    guess.integrations = model.integrations();
  }
  return guess;
}

}  // namespace terratraj::ocp
