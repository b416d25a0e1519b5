#include "terratraj/ocp/ceres_solver.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "solve_accounting.hpp"
#include "terratraj/ocp/newton_solver.hpp"

namespace terratraj::ocp {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr double kMinFinalTime = 1e-3;  // lower bound of t_f [s]

// The augmented-Lagrangian residuals (r0, r_c) of one parameter block q. Evaluations are
// cached on q with sensitivities (Ceres asks for the residuals of a trial point, then for the
// Jacobian at the same point once accepted): one integration per new q. Returns false, and
// never throws, when the integration fails.
class AugmentedLagrangianResiduals final : public ceres::CostFunction {
 public:
  explicit AugmentedLagrangianResiduals(ParametricTrajectoryModel& model)
      : model_(model), n_(model.parameterCount()) {
    set_num_residuals(4);
    mutable_parameter_block_sizes()->push_back(n_);
  }

  void setMultipliers(const Eigen::Vector3d& lambda, double mu) {
    lambda_ = lambda;
    mu_ = mu;
  }

  // Evaluates the model at q (cached). False when the integration fails or gives J <= 0.
  bool update(const double* x) const {
    const Eigen::Map<const Eigen::VectorXd> q(x, n_);
    if (has_cache_ && q == cache_q_) return cache_ok_;
    has_cache_ = true;
    cache_q_ = q;
    cache_ok_ = model_.evaluate(cache_q_, DerivativeMode::kSensitivity, eval_) &&
                eval_.cost > 0.0 && std::isfinite(eval_.cost) && eval_.gradient.allFinite() &&
                eval_.jacobian.allFinite();
    if (!cache_ok_ && eval_.ok()) eval_.message = "non-positive or non-finite cost";
    return cache_ok_;
  }

  const ParametricEvaluation& evaluation() const { return eval_; }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    try {
      if (!update(parameters[0])) return false;
      const double r0 = std::sqrt(2.0 * eval_.cost);
      const double root_mu = std::sqrt(mu_);
      residuals[0] = r0;
      Eigen::Map<Eigen::Vector3d>(residuals + 1) = root_mu * (eval_.terminal_error + lambda_ / mu_);
      if (jacobians != nullptr && jacobians[0] != nullptr) {
        Eigen::Map<RowMajorMatrix> d(jacobians[0], 4, n_);
        d.row(0) = eval_.gradient.transpose() / r0;
        d.bottomRows<3>() = root_mu * eval_.jacobian;
      }
      return true;
    } catch (...) {
      return false;
    }
  }

 private:
  ParametricTrajectoryModel& model_;
  int n_;
  Eigen::Vector3d lambda_ = Eigen::Vector3d::Zero();
  double mu_ = 1.0;
  mutable bool has_cache_ = false;
  mutable bool cache_ok_ = false;
  mutable Eigen::VectorXd cache_q_;
  mutable ParametricEvaluation eval_;
};

// Why `options` cannot be used, or nothing.
std::optional<std::string> optionsError(const CeresOptions& options) {
  if (options.max_iterations < 1 || options.max_outer_iterations < 1) {
    return "max_iterations and max_outer_iterations must be >= 1";
  }
  if (!(options.initial_penalty > 0.0) || !std::isfinite(options.initial_penalty)) {
    return "initial_penalty must be a positive number";
  }
  if (options.time_limit_s && !(*options.time_limit_s >= 0.0)) {
    return "time_limit_s must be >= 0";
  }
  return std::nullopt;
}

// Ends an inner solve when a stop is requested (SIGINT).
class StopOnRequest : public ceres::IterationCallback {
 public:
  explicit StopOnRequest(const std::atomic<bool>* stop) : stop_(stop) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return stop_ != nullptr && stop_->load() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::atomic<bool>* stop_;
};

// The inner (trust-region) solves' settings.
ceres::Solver::Options innerSolverOptions(const ConvergenceCriteria& criteria) {
  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = 1;
  // Inner solves end on the gradient of the augmented Lagrangian, g + A' (lambda + mu c):
  // the next multipliers' stationarity.
  solver_options.gradient_tolerance = 0.1 * criteria.lagrangian_gradient;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  return solver_options;
}

SolveResult runCeres(ParametricTrajectoryModel& model, const Eigen::VectorXd& q0,
                     const CeresOptions& options, SolveResult& result,
                     const detail::SolveAccounting& accounting) {
  const auto finish = [&](SolveStatus status, std::string reason) {
    return accounting.finish(status, std::move(reason));
  };
  const int n = model.parameterCount();
  const int itf = model.finalTimeIndex();
  const ConvergenceCriteria& criteria = options.criteria;
  if (q0.size() != n) return finish(SolveStatus::kError, "initial guess has the wrong size");
  if (const std::optional<std::string> error = optionsError(options)) {
    return finish(SolveStatus::kError, *error);
  }

  // Owned here, not by the problem.
  AugmentedLagrangianResiduals residuals(model);
  Eigen::VectorXd q = q0;
  if (!residuals.update(q.data())) {
    return finish(SolveStatus::kDiverged, "initial guess: " + residuals.evaluation().message);
  }
  // Inside the bound (a positive t_f below it would make Ceres reject the problem).
  if (q(itf) < kMinFinalTime) {
    q(itf) = kMinFinalTime;
    if (!residuals.update(q.data())) {
      return finish(SolveStatus::kDiverged, "initial guess with t_f raised to its bound: " +
                                                residuals.evaluation().message);
    }
  }
  const auto record = [&](int outer, const ParametricEvaluation& at, double stationarity) {
    result.q = q;
    result.cost = at.cost;
    result.terminal_error = at.terminal_error;
    result.history.push_back({outer, at.terminal_error.head<2>().norm(),
                              std::abs(at.terminal_error.z()), at.cost, stationarity,
                              std::numeric_limits<double>::quiet_NaN()});
  };
  Eigen::Vector3d lambda =
      leastSquaresMultipliers(residuals.evaluation().jacobian, residuals.evaluation().gradient);
  result.lambda = lambda;
  record(0, residuals.evaluation(),
         (residuals.evaluation().gradient + residuals.evaluation().jacobian.transpose() * lambda)
             .lpNorm<Eigen::Infinity>());
  double mu = options.initial_penalty;
  double previous_violation = residuals.evaluation().terminal_error.norm();

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  problem.AddResidualBlock(&residuals, nullptr, q.data());
  problem.SetParameterLowerBound(q.data(), itf, kMinFinalTime);

  ceres::Solver::Options solver_options = innerSolverOptions(criteria);
  StopOnRequest stop_on_request(options.stop);
  if (options.stop != nullptr) solver_options.callbacks.push_back(&stop_on_request);

  int used = 0;
  for (int outer = 1; outer <= options.max_outer_iterations; ++outer) {
    if (used >= options.max_iterations) {
      return finish(
          SolveStatus::kMaxIterations,
          "max_iterations = " + std::to_string(options.max_iterations) + " Ceres iterations used");
    }
    double remaining_s = 1e9;
    if (options.time_limit_s) remaining_s = *options.time_limit_s - accounting.elapsedSeconds();
    if (remaining_s <= 0.0 || accounting.pastTimeLimit(std::nullopt, options.stop)) {
      return accounting.finishOnTimeLimit(options.time_limit_s, options.stop);
    }
    solver_options.max_num_iterations = options.max_iterations - used;
    solver_options.max_solver_time_in_seconds = remaining_s;
    residuals.setMultipliers(lambda, mu);
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    used += summary.num_successful_steps + summary.num_unsuccessful_steps;
    result.iterations = used;
    if (accounting.pastTimeLimit(std::nullopt, options.stop)) {
      return accounting.finishOnTimeLimit(options.time_limit_s, options.stop);
    }
    if (summary.termination_type == ceres::FAILURE ||
        summary.termination_type == ceres::USER_FAILURE) {
      const std::string message =
          residuals.evaluation().ok()
              ? summary.message
              : summary.message + " (" + residuals.evaluation().message + ")";
      return finish(SolveStatus::kDiverged,
                    "outer iteration " + std::to_string(outer) + ": Ceres failed: " + message);
    }
    if (!residuals.update(q.data())) {
      return finish(SolveStatus::kDiverged, "outer iteration " + std::to_string(outer) + ": " +
                                                residuals.evaluation().message);
    }
    const ParametricEvaluation& at = residuals.evaluation();
    lambda += mu * at.terminal_error;
    const double stationarity =
        (at.gradient + at.jacobian.transpose() * lambda).lpNorm<Eigen::Infinity>();
    result.lambda = lambda;
    record(outer, at, stationarity);
    if (!lambda.allFinite()) {
      return finish(SolveStatus::kDiverged, "the multipliers are not finite");
    }
    if (at.terminal_error.head<2>().norm() <= criteria.position_m &&
        std::abs(at.terminal_error.z()) <= criteria.heading_rad &&
        stationarity <= criteria.lagrangian_gradient) {
      return finish(SolveStatus::kConverged, "");
    }
    const double violation = at.terminal_error.norm();
    if (violation > 0.25 * previous_violation) mu *= 10.0;
    previous_violation = violation;
  }
  std::ostringstream text;
  text << "max_outer_iterations = " << options.max_outer_iterations << " reached (terminal error "
       << result.terminal_error.head<2>().norm() << " m, " << std::abs(result.terminal_error.z())
       << " rad, Lagrangian gradient " << result.history.back().lagrangian_gradient << ")";
  return finish(SolveStatus::kMaxIterations, text.str());
}

}  // namespace

SolveResult solveCeres(ParametricTrajectoryModel& model, const Eigen::VectorXd& q0,
                       const CeresOptions& options) {
  SolveResult result;
  result.q = q0;
  const detail::SolveAccounting accounting(model, result, "ceres");
  return detail::guardThirdParty("Ceres", accounting,
                                 [&] { return runCeres(model, q0, options, result, accounting); });
}

}  // namespace terratraj::ocp
