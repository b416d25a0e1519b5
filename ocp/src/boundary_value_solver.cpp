#include "terratraj/ocp/boundary_value_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "terratraj/ocp/ceres_solver.hpp"
#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/ipopt_solver.hpp"
#include "terratraj/ocp/newton_solver.hpp"
#include "terratraj/ocp/parametric_controls.hpp"
#include "terratraj/ocp/path_constraints.hpp"
#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/ocp/start_at_goal.hpp"

namespace terratraj::ocp {
namespace {

using Clock = std::chrono::steady_clock;

SolveResult runSolver(const models::TerrainFollowingModel& vehicle,
                      const BoundaryValueProblem& problem, const BoundaryValueOptions& options,
                      const InitialGuess& guess) {
  ParametricModelOptions model_options;
  model_options.integrator = options.integrator;
  if (options.time_limit_s) {
    model_options.integrator.deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(*options.time_limit_s));
  }
  NewtonOptions newton;
  newton.criteria = options.criteria;
  newton.max_iterations = options.max_iterations;
  newton.time_limit_s = options.time_limit_s;
  newton.stop = options.stop;
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
      const PathConstraints constraints(problem.limits, problem.tables, options.segway_bound_scale);
      IpoptOptions ipopt;
      ipopt.criteria = options.criteria;
      ipopt.max_iterations = options.max_iterations;
      ipopt.time_limit_s = options.time_limit_s;
      ipopt.stop = options.stop;
      ipopt.path_points = options.path_points;
      if (options.max_final_time_ratio > 0.0) {
        ipopt.max_final_time_s =
            options.max_final_time_ratio * std::max(guess.q(model.finalTimeIndex()), 1e-2);
      }
      return solveIpopt(model, &constraints, guess.q, ipopt);
    }
    case BoundaryValueMethod::kCeres: {
      ParametricTrajectoryModel model(vehicle, problem, model_options);
      CeresOptions ceres;
      ceres.criteria = options.criteria;
      ceres.max_iterations = options.max_iterations;
      ceres.time_limit_s = options.time_limit_s;
      ceres.stop = options.stop;
      return solveCeres(model, guess.q, ceres);
    }
  }
  return {};
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
  const Deadline clock(started, options.time_limit_s, options.stop);  // or a stop
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
    // Whatever step the clock stopped (the initial guess's integration included), a result
    // short of converged at the time limit is unfinished.
    if (status != SolveStatus::kConverged && clock.over()) solution.time_limit_reached = true;
    return solution;
  };
  if (startMeetsGoal(problem, options.criteria)) {
    // Nothing to drive: the one-row trajectory at the start, judged like any other.
    solution.solver.status = SolveStatus::kConverged;
    if (std::optional<models::Trajectory> here = startOnlyTrajectory(vehicle, problem)) {
      solution.verified.ok = true;
      solution.verified.trajectory = std::move(*here);
      solution.verified.max_speed = problem.start.v;
      solution.verdict = models::judgeTrajectory(
          solution.verified.trajectory, solveRequirements(vehicle, problem, options.criteria, map));
    }
    const SolveStatus status = solution.verified.ok
                                   ? statusAfterVerdict(SolveStatus::kConverged, solution.verdict)
                                   : SolveStatus::kInfeasible;
    return finish(status,
                  status == SolveStatus::kConverged
                      ? "the start already meets the goal: nothing to drive"
                      : "the start meets the goal but fails the check: " + solution.verdict.reason);
  }
  if (const std::optional<std::string> problem_error = validateProblem(problem)) {
    return finish(SolveStatus::kInfeasible, *problem_error);
  }
  const int unknowns =
      ParametricControls(problem.start, problem.goal, problem.orders).parameterCount();
  GuessDeadline guess_deadline;
  if (options.time_limit_s) {
    guess_deadline = started + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(*options.time_limit_s));
  }
  solution.initial_guess =
      options.initial_q.size() == unknowns
          ? flatInitialGuess(problem, vehicle.surface(), options.initial_q, guess_deadline)
          : flatInitialGuess(problem, vehicle.surface(), guess_deadline);
  if (!solution.initial_guess.ok) {
    // Stopped by the clock: as a solver stopped by it (the fallback in finish() says so).
    const bool timed_out = guess_deadline && Clock::now() > *guess_deadline;
    solution.solver.status = timed_out ? SolveStatus::kMaxIterations : SolveStatus::kInfeasible;
    return finish(solution.solver.status, solution.initial_guess.reason);
  }
  // The solver aims inside the criteria, so that the re-simulation (tighter integration) and
  // the CSV's rounding cannot push a converged end over the verdict's tolerance.
  BoundaryValueOptions solver_options = options;
  // The solver gets what the guess left of the time limit.
  if (options.time_limit_s) {
    solver_options.time_limit_s = std::max(0.0, *options.time_limit_s - 1e-3 * elapsed_ms());
  }
  solver_options.criteria.position_m *= 0.5;
  solver_options.criteria.heading_rad *= 0.5;
  solution.path_points = options.method == BoundaryValueMethod::kIpopt ? options.path_points : 0;
  solution.solver = runSolver(vehicle, problem, solver_options, solution.initial_guess);
  if (solution.solver.q.size() == 0) solution.solver.q = solution.initial_guess.q;
  double verification_ms = 0.0;
  const auto verify = [&] {
    // A solve stopped by the time limit is not re-simulated (the re-simulation of a wild
    // iterate can take seconds): its status already says why it ended.
    if (solution.solver.status != SolveStatus::kConverged && clock.over()) {
      solution.verified = VerifiedTrajectory();
      solution.verified.message =
          "not re-simulated: the time limit was reached or a stop requested";
      return;
    }
    const double before = elapsed_ms();
    solution.verified =
        verifyParametricSolution(vehicle, problem, solution.solver.q, map, options.verification);
    if (solution.verified.ok) {
      solution.verdict = models::judgeTrajectory(
          solution.verified.trajectory, solveRequirements(vehicle, problem, options.criteria, map));
    }
    verification_ms += elapsed_ms() - before;
  };
  verify();
  // ipopt holds the limits at path points only (the Segway's look-ups included, by their C1
  // versions): a limit broken between them is held at twice as many points, from the solution
  // found, up to max_path_points.
  while (options.method == BoundaryValueMethod::kIpopt &&
         solution.solver.status == SolveStatus::kConverged && solution.verified.ok &&
         solution.verdict.failure == models::VerdictFailure::kBreaksLimits &&
         solution.path_points < options.max_path_points) {
    if (clock.over()) {
      solution.time_limit_reached = true;
      break;
    }
    solution.path_points = std::min(2 * solution.path_points - 1, options.max_path_points);
    solver_options.path_points = solution.path_points;
    if (options.time_limit_s) {
      solver_options.time_limit_s = std::max(0.0, *options.time_limit_s - 1e-3 * elapsed_ms());
    }
    InitialGuess from_solution = solution.initial_guess;
    from_solution.q = solution.solver.q;
    const int iterations = solution.solver.iterations;
    std::vector<IterationRecord> history = std::move(solution.solver.history);
    solution.solver = runSolver(vehicle, problem, solver_options, from_solution);
    if (solution.solver.q.size() == 0) solution.solver.q = from_solution.q;
    solution.solver.iterations += iterations;
    history.insert(history.end(), solution.solver.history.begin(), solution.solver.history.end());
    solution.solver.history = std::move(history);
    verify();
  }
  solution.total_time_ms = elapsed_ms() - verification_ms;
  solution.time_limit_reached = solution.time_limit_reached || solution.solver.time_limit_reached;
  timed = true;
  solution.verification_time_ms = verification_ms;
  if (solution.solver.status != SolveStatus::kConverged) {
    return finish(solution.solver.status, solution.solver.reason);
  }
  if (!solution.verified.ok) return finish(SolveStatus::kDiverged, solution.verified.message);
  const SolveStatus status = statusAfterVerdict(SolveStatus::kConverged, solution.verdict);
  if (status == SolveStatus::kConverged) return finish(status, "");
  std::string reason = solution.verdict.reason;
  if (status == SolveStatus::kInfeasible && options.method != BoundaryValueMethod::kIpopt) {
    reason += std::string(" (") + boundaryValueMethodName(options.method) +
              " does not enforce the vehicle limits; ipopt does)";
  }
  return finish(status, reason);
}

}  // namespace terratraj::ocp
