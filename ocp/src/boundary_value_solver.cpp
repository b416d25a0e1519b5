#include "terratraj/ocp/boundary_value_solver.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "terratraj/ocp/ceres_solver.hpp"
#include "terratraj/ocp/ipopt_solver.hpp"
#include "terratraj/ocp/newton_solver.hpp"
#include "terratraj/ocp/path_constraints.hpp"

namespace terratraj::ocp {
namespace {

using Clock = std::chrono::steady_clock;

SolveResult runSolver(const models::TerrainFollowingModel& vehicle,
                      const BoundaryValueProblem& problem, const BoundaryValueOptions& options,
                      const InitialGuess& guess) {
  ParametricModelOptions model_options;
  model_options.integrator = options.integrator;
  NewtonOptions newton;
  newton.criteria = options.criteria;
  newton.max_iterations = options.max_iterations;
  newton.time_limit_s = options.time_limit_s;
  switch (options.method) {
    case BoundaryValueMethod::kNewton: {
      ParametricTrajectoryModel model(vehicle, problem, model_options);
      return solveNewton(model, {guess.q, guess.lambda, guess.hessian}, newton, "newton");
    }
    case BoundaryValueMethod::kNewtonFd: {
      // The paper's iteration: forward differences (eq. 10, e = 1e-6) of a fixed-step map, and
      // the Hessian by eq. 11 with e = 1e-4 (1e-6 leaves only rounding noise in a second
      // difference).
      model_options.integrator.method = models::IntegrationMethod::kRk4;
      model_options.integrator.step = options.newton_fd_step;
      model_options.finite_difference_step = 1e-6;
      ParametricTrajectoryModel model(vehicle, problem, model_options);
      newton.derivatives = DerivativeMode::kFiniteDifference;
      newton.hessian = HessianApproximation::kFiniteDifference;
      newton.hessian_step = 1e-4;
      return solveNewton(model, {guess.q, guess.lambda, Eigen::MatrixXd()}, newton, "newton_fd");
    }
    case BoundaryValueMethod::kIpopt: {
      ParametricTrajectoryModel model(vehicle, problem, model_options);
      const PathConstraints constraints(problem.limits, problem.tables);
      IpoptOptions ipopt;
      ipopt.criteria = options.criteria;
      ipopt.max_iterations = options.max_iterations;
      ipopt.time_limit_s = options.time_limit_s;
      ipopt.path_points = options.path_points;
      return solveIpopt(model, &constraints, guess.q, ipopt);
    }
    case BoundaryValueMethod::kCeres: {
      ParametricTrajectoryModel model(vehicle, problem, model_options);
      CeresOptions ceres;
      ceres.criteria = options.criteria;
      ceres.max_iterations = options.max_iterations;
      ceres.time_limit_s = options.time_limit_s;
      return solveCeres(model, guess.q, ceres);
    }
  }
  return {};
}

std::string describe(const LimitViolation& violation) {
  std::ostringstream text;
  text << "limit " << violation.limit << " exceeded by " << violation.amount
       << " at t = " << violation.t << " s";
  return text.str();
}

}  // namespace

const char* boundaryValueMethodName(BoundaryValueMethod method) {
  switch (method) {
    case BoundaryValueMethod::kNewton:
      return "newton";
    case BoundaryValueMethod::kNewtonFd:
      return "newton_fd";
    case BoundaryValueMethod::kIpopt:
      return "ipopt";
    case BoundaryValueMethod::kCeres:
      return "ceres";
  }
  return "unknown";
}

BoundaryValueSolution solveBoundaryValue(const models::TerrainFollowingModel& vehicle,
                                         const BoundaryValueProblem& problem,
                                         const BoundaryValueOptions& options,
                                         const terrain::ElevationMap* map) {
  const Clock::time_point started = Clock::now();
  BoundaryValueSolution solution;
  solution.solver.method = boundaryValueMethodName(options.method);
  const auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - started).count();
  };
  bool timed = false;
  const auto finish = [&](SolveStatus status, std::string reason) {
    solution.status = status;
    solution.reason = std::move(reason);
    if (!timed) solution.total_time_ms = elapsed_ms();
    return solution;
  };
  if (const std::optional<std::string> problem_error = validateProblem(problem)) {
    return finish(SolveStatus::kInfeasible, *problem_error);
  }
  solution.initial_guess = flatInitialGuess(problem, vehicle.surface());
  if (!solution.initial_guess.ok) {
    solution.solver.status = SolveStatus::kInfeasible;
    return finish(SolveStatus::kInfeasible, solution.initial_guess.reason);
  }
  solution.solver = runSolver(vehicle, problem, options, solution.initial_guess);
  if (solution.solver.q.size() == 0) solution.solver.q = solution.initial_guess.q;
  solution.total_time_ms = elapsed_ms();
  timed = true;
  solution.verified =
      verifyParametricSolution(vehicle, problem, solution.solver.q, map, options.verification);
  solution.verification_time_ms = elapsed_ms() - solution.total_time_ms;
  if (solution.solver.status != SolveStatus::kConverged) {
    return finish(solution.solver.status, solution.solver.reason);
  }
  if (!solution.verified.ok) return finish(SolveStatus::kDiverged, solution.verified.message);
  const Eigen::Vector3d& error = solution.verified.terminal_error;
  // The solver integrates at looser tolerances than the re-simulation: allow for the gap.
  const double slack = 1e-5;
  if (error.head<2>().norm() > options.criteria.position_m + slack ||
      std::abs(error.z()) > options.criteria.heading_rad + slack) {
    std::ostringstream text;
    text << "the re-simulated trajectory misses the goal by " << error.head<2>().norm() << " m and "
         << std::abs(error.z()) << " rad";
    return finish(SolveStatus::kDiverged, text.str());
  }
  if (solution.verified.violation.amount > options.limit_tolerance) {
    std::string reason = describe(solution.verified.violation);
    if (options.method != BoundaryValueMethod::kIpopt) {
      reason += std::string(" (") + boundaryValueMethodName(options.method) +
                " does not enforce the vehicle limits; ipopt does)";
    }
    return finish(SolveStatus::kInfeasible, reason);
  }
  return finish(SolveStatus::kConverged, "");
}

}  // namespace terratraj::ocp
