#include "terratraj/ocp/newton_solver.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "solve_accounting.hpp"

namespace terratraj::ocp {
namespace {

bool converged(const ParametricEvaluation& at, double stationarity,
               const ConvergenceCriteria& criteria) {
  return at.terminal_error.head<2>().norm() <= criteria.position_m &&
         std::abs(at.terminal_error.z()) <= criteria.heading_rad &&
         stationarity <= criteria.lagrangian_gradient;
}

double merit(const ParametricEvaluation& at, double nu) {
  return at.cost + nu * at.terminal_error.lpNorm<1>();
}

// W made positive definite on the null space of A (so that the KKT step is a descent
// direction of the merit): adds tau I until Z' (W + tau I) Z has eigenvalues >= floor.
Eigen::MatrixXd convexified(const Eigen::MatrixXd& w, const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(w.rows());
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const int rank = static_cast<int>((svd.singularValues().array() > 1e-10).count());
  if (rank >= n) return w;
  const Eigen::MatrixXd z = svd.matrixV().rightCols(n - rank);
  const Eigen::MatrixXd reduced = z.transpose() * w * z;
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(reduced, Eigen::EigenvaluesOnly)
          .eigenvalues()
          .minCoeff();
  const double floor = 1e-6 * std::max(1.0, w.diagonal().cwiseAbs().maxCoeff());
  if (smallest >= floor) return w;
  return w + (floor - smallest) * Eigen::MatrixXd::Identity(n, n);
}

void dampedBfgsUpdate(const Eigen::VectorXd& s, const Eigen::VectorXd& y, Eigen::MatrixXd& w) {
  const Eigen::VectorXd ws = w * s;
  const double sws = s.dot(ws);
  const double sy = s.dot(y);
  if (!(sws > 1e-16)) return;
  // Powell's damping keeps W positive definite.
  const double theta = sy >= 0.2 * sws ? 1.0 : 0.8 * sws / (sws - sy);
  const Eigen::VectorXd r = theta * y + (1.0 - theta) * ws;
  const double sr = s.dot(r);
  if (!(sr > 1e-16)) return;
  w += r * r.transpose() / sr - ws * ws.transpose() / sws;
}

// Backtracking on the l1 merit from q along d, from alpha (in: the largest step; out: the step
// taken), at most 40 halvings, with one second-order correction against the Maratos effect (a
// projection back onto c = 0). Without options.line_search the full step is taken. On success
// q_next and trial hold the accepted point; otherwise `why` says why.
bool lineSearch(ParametricTrajectoryModel& model, const NewtonOptions& options,
                const ParametricEvaluation& current, const Eigen::VectorXd& q,
                const Eigen::VectorXd& d, double nu, ParametricEvaluation& trial,
                ParametricEvaluation& correction, Eigen::VectorXd& q_next, double& alpha,
                std::string& why) {
  const DerivativeMode mode = options.derivatives;
  const int itf = model.finalTimeIndex();
  const double merit0 = merit(current, nu);
  const double slope = current.gradient.dot(d) - nu * current.terminal_error.lpNorm<1>();
  for (int trial_count = 0; trial_count < 40; ++trial_count, alpha *= 0.5) {
    q_next = q + alpha * d;
    const bool ok = model.evaluate(q_next, mode, trial);
    if (!options.line_search) {
      if (!ok) why = "full Newton step: " + trial.message;
      return ok;
    }
    if (ok && merit(trial, nu) <= merit0 + 1e-4 * alpha * std::min(slope, 0.0)) return true;
    if (ok && trial_count == 0) {
      const Eigen::MatrixXd& a = current.jacobian;
      const Eigen::VectorXd soc =
          -a.transpose() *
          (a * a.transpose()).completeOrthogonalDecomposition().solve(trial.terminal_error);
      Eigen::VectorXd q_soc = q_next + soc;
      if (q_soc(itf) > options.min_final_time_s && model.evaluate(q_soc, mode, correction) &&
          merit(correction, nu) <= merit0 + 1e-4 * alpha * std::min(slope, 0.0)) {
        q_next = q_soc;
        std::swap(trial, correction);
        return true;
      }
    }
    if (alpha < 1e-8) break;
  }
  why = "the line search found no decrease of the merit function (the last trial: " +
        (trial.ok() ? std::string("no decrease") : trial.message) + ")";
  return false;
}

}  // namespace

Eigen::Vector3d leastSquaresMultipliers(const Eigen::MatrixXd& jacobian,
                                        const Eigen::VectorXd& gradient) {
  const Eigen::Matrix3d aat = jacobian * jacobian.transpose();
  const Eigen::Vector3d rhs = -(jacobian * gradient);
  return aat.completeOrthogonalDecomposition().solve(rhs);
}

SolveResult solveNewton(ParametricTrajectoryModel& model, const NewtonStart& start,
                        const NewtonOptions& options, const char* method) {
  SolveResult result;
  const detail::SolveAccounting accounting(model, result, method);
  const int n = model.parameterCount();
  const int itf = model.finalTimeIndex();
  const DerivativeMode mode = options.derivatives;
  const auto finish = [&](SolveStatus status, std::string reason) {
    return accounting.finish(status, std::move(reason));
  };

  ParametricEvaluation current, trial, correction;
  Eigen::VectorXd q = start.q;
  result.q = q;
  if (q.size() != n) return finish(SolveStatus::kError, "initial guess has the wrong size");
  if (!model.evaluate(q, mode, current)) {
    return finish(SolveStatus::kDiverged, "initial guess: " + current.message);
  }
  Eigen::Vector3d lambda =
      start.lambda ? *start.lambda : leastSquaresMultipliers(current.jacobian, current.gradient);
  Eigen::MatrixXd w;
  if (start.hessian.rows() == n && start.hessian.cols() == n) {
    w = start.hessian;
  } else {
    w = Eigen::MatrixXd::Identity(n, n);
  }
  double nu = 0.0;
  double last_step = 0.0;
  Eigen::MatrixXd kkt(n + 3, n + 3);
  Eigen::VectorXd rhs(n + 3);

  for (int iteration = 0;; ++iteration) {
    result.q = q;
    result.cost = current.cost;
    result.terminal_error = current.terminal_error;
    result.lambda = lambda;
    const Eigen::Vector3d lambda_ls = leastSquaresMultipliers(current.jacobian, current.gradient);
    const double stationarity =
        (current.gradient + current.jacobian.transpose() * lambda_ls).lpNorm<Eigen::Infinity>();
    result.history.push_back({iteration, current.terminal_error.head<2>().norm(),
                              std::abs(current.terminal_error.z()), current.cost, stationarity,
                              last_step});
    result.iterations = iteration;
    if (converged(current, stationarity, options.criteria)) {
      result.lambda = lambda_ls;
      return finish(SolveStatus::kConverged, "");
    }
    if (iteration >= options.max_iterations) {
      return finish(SolveStatus::kMaxIterations,
                    "max_iterations = " + std::to_string(options.max_iterations) + " reached");
    }
    if (accounting.pastTimeLimit(options.time_limit_s, options.stop)) {
      return accounting.finishOnTimeLimit(options.time_limit_s, options.stop);
    }
    if (options.hessian == HessianApproximation::kFiniteDifference) {
      if (!model.lagrangianHessian(q, lambda, mode, options.hessian_step, w)) {
        return finish(SolveStatus::kDiverged, "Hessian: an integration failed near the iterate");
      }
    }
    const Eigen::MatrixXd w_convex = convexified(w, current.jacobian);
    kkt.setZero();
    kkt.topLeftCorner(n, n) = w_convex;
    kkt.topRightCorner(n, 3) = current.jacobian.transpose();
    kkt.bottomLeftCorner(3, n) = current.jacobian;
    rhs.head(n) = -current.gradient;
    rhs.tail(3) = -current.terminal_error;
    const Eigen::VectorXd solution = kkt.colPivHouseholderQr().solve(rhs);
    if (!solution.allFinite()) return finish(SolveStatus::kDiverged, "the KKT system is singular");
    const Eigen::VectorXd d = solution.head(n);
    const Eigen::Vector3d lambda_next = solution.tail(3);

    // Step length: keep t_f above its floor, then backtrack on the merit.
    double alpha_max = 1.0;
    const double tf = q(itf);
    if (d(itf) < 0.0) {
      alpha_max = std::min(1.0, 0.9 * (tf - options.min_final_time_s) / -d(itf));
      if (!(alpha_max > 1e-10)) {
        return finish(SolveStatus::kDiverged,
                      "t_f collapsed to " + std::to_string(tf) +
                          " s: the cost decreases without bound as the trajectory shortens");
      }
    }
    nu = std::max(nu, 1.1 * lambda_next.lpNorm<Eigen::Infinity>() + 1e-3);
    double alpha = alpha_max;
    Eigen::VectorXd q_next;
    std::string why;
    if (!lineSearch(model, options, current, q, d, nu, trial, correction, q_next, alpha, why)) {
      return finish(SolveStatus::kDiverged, why);
    }
    if (options.hessian == HessianApproximation::kBfgs) {
      const Eigen::VectorXd grad_old =
          current.gradient + current.jacobian.transpose() * lambda_next;
      const Eigen::VectorXd grad_new = trial.gradient + trial.jacobian.transpose() * lambda_next;
      dampedBfgsUpdate(q_next - q, grad_new - grad_old, w);
    }
    q = q_next;
    std::swap(current, trial);
    lambda = lambda_next;
    last_step = alpha;
  }
}

}  // namespace terratraj::ocp
