#include "terratraj/apps/solve_command.hpp"

#include <cmath>
#include <limits>
#include <ostream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/vehicle_factory.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_source.hpp"

namespace terratraj::apps {
namespace {

ocp::VehicleState toState(const BoundaryState& s) { return {s.x, s.y, s.heading, s.v, s.omega}; }

std::optional<ocp::BoundaryValueMethod> parametricMethod(SolverMethod method) {
  switch (method) {
    case SolverMethod::kNewton:
      return ocp::BoundaryValueMethod::kNewton;
    case SolverMethod::kNewtonFd:
      return ocp::BoundaryValueMethod::kNewtonFd;
    case SolverMethod::kIpopt:
      return ocp::BoundaryValueMethod::kIpopt;
    case SolverMethod::kCeres:
      return ocp::BoundaryValueMethod::kCeres;
    case SolverMethod::kShooting:
    case SolverMethod::kCollocation:
      return std::nullopt;
  }
  return std::nullopt;
}

// JSON has no NaN: unknown values are null.
nlohmann::json number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

ocp::BoundaryValueProblem boundaryValueProblem(const ProblemSpec& problem) {
  ocp::BoundaryValueProblem bvp;
  bvp.start = toState(problem.start);
  bvp.goal = toState(problem.goal);
  bvp.cost.kind = problem.cost.kind == CostKind::kSlopeDwell ? ocp::CostKind::kSlopeDwell
                                                             : ocp::CostKind::kTime;
  bvp.cost.alpha = problem.cost.alpha;
  bvp.orders = {problem.solver.yaw_rate_order, problem.solver.speed_order};
  bvp.limits = problem.vehicle.limits;
  return bvp;
}

ocp::BoundaryValueOptions boundaryValueOptions(const ProblemSpec& problem) {
  ocp::BoundaryValueOptions options;
  const std::optional<ocp::BoundaryValueMethod> method = parametricMethod(problem.solver.method);
  if (!method) {
    throw InputError(problem.source_file.string() +
                     ": solver.method: " + solverMethodName(problem.solver.method) +
                     " is a direct-transcription method, which `solve` does not provide yet; "
                     "use newton, newton_fd, ipopt or ceres");
  }
  options.method = *method;
  options.criteria = {problem.solver.tolerance_position_m, problem.solver.tolerance_heading_rad,
                      problem.solver.tolerance_lagrangian_gradient};
  options.max_iterations = problem.solver.max_iterations;
  options.time_limit_s = problem.solver.time_limit_s;
  return options;
}

nlohmann::json solveReportJson(const ocp::BoundaryValueSolution& solution,
                               const ocp::BoundaryValueOptions& options) {
  const ocp::VerifiedTrajectory& v = solution.verified;
  const ocp::SolveResult& s = solution.solver;
  nlohmann::json history = nlohmann::json::array();
  for (const ocp::IterationRecord& r : s.history) {
    history.push_back({{"iteration", r.iteration},
                       {"terminal_error", number(r.terminal_error)},
                       {"heading_error", number(r.heading_error)},
                       {"cost", number(r.cost)},
                       {"lagrangian_gradient", number(r.lagrangian_gradient)},
                       {"step", number(r.step)}});
  }
  nlohmann::json json{
      {"status", ocp::solveStatusName(solution.status)},
      {"reason", solution.reason},
      {"method", ocp::boundaryValueMethodName(options.method)},
      {"iterations", s.iterations},
      {"max_iterations", options.max_iterations},
      {"time_limit_s",
       options.time_limit_s ? nlohmann::json(*options.time_limit_s) : nlohmann::json(nullptr)},
      {"solve_time_ms", solution.total_time_ms},
      {"solver_time_ms", s.solve_time_ms},
      {"integrations", s.integrations + solution.initial_guess.integrations},
      {"final_time_s", v.ok ? number(v.final_time) : nullptr},
      {"cost", v.ok ? number(v.cost) : nullptr},
      {"length_m", v.ok ? number(v.length) : nullptr},
      {"terminal_error",
       {{"position_m", v.ok ? number(v.terminal_error.head<2>().norm()) : nullptr},
        {"heading_rad", v.ok ? number(std::abs(v.terminal_error.z())) : nullptr}}},
      {"max_abs_pitch_rad", number(v.max_abs_pitch)},
      {"max_abs_roll_rad", number(v.max_abs_roll)},
      {"max_speed", number(v.max_speed)},
      {"constraint_violation", number(v.violation.amount)},
      {"violated_limit",
       v.violation.limit.empty() ? nlohmann::json(nullptr) : nlohmann::json(v.violation.limit)},
      {"slope_dwell_rad2_s", number(v.slope_dwell)},
      {"verified", v.ok},
      {"tolerance",
       {{"position_m", options.criteria.position_m},
        {"heading_rad", options.criteria.heading_rad},
        {"lagrangian_gradient", options.criteria.lagrangian_gradient}}},
      {"controls", std::vector<double>(s.q.data(), s.q.data() + s.q.size())},
      {"history", history},
  };
  return json;
}

nlohmann::json solveDemoProblem(const terrain::ElevationMap& map, const std::filesystem::path& csv,
                                CommandContext& context) {
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const std::unique_ptr<models::TerrainFollowingModel> vehicle =
      makeTerrainFollowingModel(VehicleModelKind::kRockerBogie, surface);
  ocp::BoundaryValueProblem bvp;
  const double x0 = 0.15 * map.geometry().width(), y0 = 0.4 * map.geometry().height();
  bvp.start = {x0, y0, 0.0, 0.5, 0.0};
  bvp.goal = {x0 + 6.0, y0 + 1.5, 0.3, 0.5, 0.0};
  bvp.cost = {ocp::CostKind::kSlopeDwell, 1.0};
  bvp.limits.kappa_max = 2.0;
  bvp.limits.sigma_max = 2.0;
  bvp.limits.pitch_max = bvp.limits.roll_max = 0.5;
  const ocp::BoundaryValueOptions options;
  context.log->info("demo: solving a boundary-value problem with newton (rocker_bogie)");
  const ocp::BoundaryValueSolution solution = ocp::solveBoundaryValue(*vehicle, bvp, options, &map);
  nlohmann::json report = solveReportJson(solution, options);
  if (solution.verified.ok) {
    models::writeTrajectoryCsv(solution.verified.trajectory, csv);
    report["file"] = csv.string();
  }
  return report;
}

int runSolve(const SolveOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  if (options.method) {
    const std::optional<SolverMethod> method = parseSolverMethod(*options.method);
    if (!method) throw InputError("--method: unknown method '" + *options.method + "'");
    problem.solver.method = *method;
  }
  const ocp::BoundaryValueOptions solve_options = boundaryValueOptions(problem);
  context.log->info("{}: loading the terrain", options.problem.string());
  const terrain::ElevationMap map = terrain::loadTerrain(problem.terrain);
  resolvePosesOnTerrain(problem, map);
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const std::unique_ptr<models::TerrainFollowingModel> vehicle =
      makeTerrainFollowingModel(problem.vehicle.model, surface);
  restingAttitude(*vehicle, problem.start, "start", problem);
  restingAttitude(*vehicle, problem.goal, "goal", problem);
  ocp::BoundaryValueProblem bvp = boundaryValueProblem(problem);
  std::optional<models::PitchSpeedTable> pitch_table;
  std::optional<models::RollCurvatureSpeedTable> roll_table;
  if (problem.vehicle.tables.pitch) {
    pitch_table = models::readPitchTable(*problem.vehicle.tables.pitch);
    bvp.tables.pitch = &*pitch_table;
  }
  if (problem.vehicle.tables.roll_curvature) {
    roll_table = models::readRollCurvatureTable(*problem.vehicle.tables.roll_curvature);
    bvp.tables.roll_curvature = &*roll_table;
  }
  context.log->info("solving with {} on the {} model",
                    ocp::boundaryValueMethodName(solve_options.method), vehicle->name());
  const ocp::BoundaryValueSolution solution =
      ocp::solveBoundaryValue(*vehicle, bvp, solve_options, &map);
  if (options.out && solution.verified.ok) {
    models::writeTrajectoryCsv(solution.verified.trajectory, *options.out);
  }
  const nlohmann::json report = solveReportJson(solution, solve_options);
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    const ocp::VerifiedTrajectory& v = solution.verified;
    context.out << ocp::solveStatusName(solution.status) << " ("
                << report["method"].get<std::string>() << ", " << solution.solver.iterations
                << " iterations, " << solution.total_time_ms << " ms)";
    if (!solution.reason.empty()) context.out << ": " << solution.reason;
    context.out << '\n';
    if (v.ok) {
      context.out << "  final time  " << v.final_time << " s, cost " << v.cost << ", length "
                  << v.length << " m\n"
                  << "  terminal    " << v.terminal_error.head<2>().norm() << " m, "
                  << std::abs(v.terminal_error.z()) << " rad (re-simulated)\n"
                  << "  attitude    max |pitch| " << v.max_abs_pitch << " rad, max |roll| "
                  << v.max_abs_roll << " rad; max speed " << v.max_speed << " m/s\n"
                  << "  violation   " << v.violation.amount
                  << (v.violation.limit.empty() ? "" : " (" + v.violation.limit + ")") << '\n';
    }
    if (options.out && v.ok) context.out << "  trajectory  " << options.out->string() << '\n';
  }
  return solution.status == ocp::SolveStatus::kConverged ? kExitSuccess : kExitNotSolved;
}

}  // namespace terratraj::apps
