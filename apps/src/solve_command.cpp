#include "terratraj/apps/solve_command.hpp"

#include <cmath>
#include <limits>
#include <ostream>

#include "terratraj/apps/cli.hpp"
#include "terratraj/apps/output_paths.hpp"
#include "terratraj/apps/plot_writer.hpp"
#include "terratraj/apps/problem_commands.hpp"
#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/apps/problem_translation.hpp"
#include "terratraj/apps/report_json.hpp"
#include "terratraj/apps/verdict_json.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/ocp/start_at_goal.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_solver.hpp"
#include "terratraj/refine/seeded_solver.hpp"
#include "terratraj/terrain/clearance_map.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {

using bench::attemptsJson;
using bench::jsonNumber;
namespace {

// The human-readable lines of a re-simulated trajectory.
void printVerifiedTrajectory(std::ostream& out, const ocp::VerifiedTrajectory& v) {
  if (!v.ok) return;
  out << "  final time  " << v.final_time << " s, cost " << v.cost << ", length " << v.length
      << " m\n"
      << "  terminal    " << v.terminal_error.head<2>().norm() << " m, "
      << std::abs(v.terminal_error.z()) << " rad (re-simulated)\n"
      << "  attitude    max |pitch| " << v.max_abs_pitch << " rad, max |roll| " << v.max_abs_roll
      << " rad; max speed " << v.max_speed << " m/s\n"
      << "  violation   " << v.violation.amount
      << (v.violation.limit.empty() ? "" : " (" + v.violation.limit + ")") << '\n';
}

}  // namespace

nlohmann::json transcriptionReportJson(const ocp::TranscriptionSolution& solution,
                                       const ocp::VerifiedTrajectory& v,
                                       const ocp::DirectTranscriptionOptions& options,
                                       const std::string& guess_source) {
  const ocp::SolveResult& s = solution.result;
  const nlohmann::json history = iterationHistoryJson(s.history, false);
  nlohmann::json active = nlohmann::json::array();
  for (const ocp::ActiveConstraint& a : solution.active) {
    active.push_back({{"limit", a.name},
                      {"t", a.t},
                      {"point", a.point},
                      {"value", a.value},
                      {"multiplier", a.multiplier}});
  }
  nlohmann::json refinement = nlohmann::json::array();
  for (const ocp::RefinementRound& r : solution.refinement) {
    refinement.push_back({{"intervals", r.intervals},
                          {"max_interval_error", r.max_interval_error},
                          {"iterations", r.iterations}});
  }
  const bool shooting = options.scheme == ocp::TranscriptionScheme::kMultipleShooting;
  nlohmann::json json{
      {"status", ocp::solveStatusName(s.status)},
      {"reason", s.reason},
      {"method", shooting ? "shooting" : "collocation"},
      {"scheme", ocp::transcriptionSchemeName(options.scheme)},
      {"shooting_controls", options.shooting_controls == ocp::ShootingControls::kPiecewiseConstant
                                ? "constant"
                                : "linear"},
      {"intervals", static_cast<int>(solution.mesh.size()) - 1},
      {"ipopt_status", solution.ipopt_status},
      {"initial_guess", guess_source},
      {"iterations", s.iterations},
      {"max_iterations", options.max_iterations},
      {"time_limit_s",
       options.time_limit_s ? nlohmann::json(*options.time_limit_s) : nlohmann::json(nullptr)},
      {"solve_time_ms", s.solve_time_ms},
      {"solver_cost", jsonNumber(s.cost)},
      {"max_defect", jsonNumber(solution.max_defect)},
      {"active_constraints", active},
      {"mesh_refinement", refinement},
      {"history", history},
  };
  json.update(verifiedTrajectoryJson(v));
  return json;
}

nlohmann::json solveReportJson(const ocp::BoundaryValueSolution& solution,
                               const ocp::BoundaryValueOptions& options) {
  const ocp::VerifiedTrajectory& v = solution.verified;
  const ocp::SolveResult& s = solution.solver;
  const nlohmann::json history = iterationHistoryJson(s.history, true);
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
      {"tolerance",
       {{"position_m", options.criteria.position_m},
        {"heading_rad", options.criteria.heading_rad},
        {"lagrangian_gradient", options.criteria.lagrangian_gradient}}},
      {"controls", std::vector<double>(s.q.data(), s.q.data() + s.q.size())},
      {"history", history},
  };
  json.update(verifiedTrajectoryJson(v));
  return json;
}

namespace {

// `--plot` of solve: the re-simulated trajectory on the map, its profiles and the iterations.
nlohmann::json plotSolve(const SolveOptions& options, const ProblemSpec& problem,
                         const ProblemScene& scene, const ocp::VerifiedTrajectory& verified,
                         const std::vector<ocp::IterationRecord>& history,
                         const std::string& method, CommandContext& context) {
  const std::filesystem::path& png = *options.plot;
  PlotRequest plot;
  plot.title = "solve (" + method + ")";
  plot.limits = problem.vehicle.limits;
  plot.start = PlotPose{scene.start().x, scene.start().y, scene.start().heading};
  plot.goal = PlotPose{scene.goal().x, scene.goal().y, scene.goal().heading};
  plot.tolerance_position_m = problem.solver.tolerance_position_m;
  if (verified.ok) {
    std::filesystem::path csv =
        options.out ? *options.out : png.parent_path() / (png.stem().string() + "-trajectory.csv");
    if (!options.out) {
      models::writeTrajectoryCsv(verified.trajectory, csv, scene.platformPitchResponse());
    }
    plot.trajectories.push_back({method, csv, false, 0});
  }
  plot.histories.push_back({method, history, 0});
  return writePlots(plot, scene.map(), png, context).toJson();
}

}  // namespace

namespace {

// The report of a seeded solve: the contract's keys, the verdict, the attempts, and the
// solver's own details (the parametric controls, or the transcription's mesh and rounds).
nlohmann::json seededReportJson(const refine::SeededSolution& solution,
                                const refine::SeededSolveOptions& seeded,
                                const ProblemSpec& problem) {
  nlohmann::json json{
      {"status", ocp::solveStatusName(solution.status)},
      {"reason", solution.reason},
      {"method", solution.method},
      {"requested_method", solverMethodName(problem.solver.method)},
      {"initial_guess", solution.initial_guess},
      {"iterations", solution.iterations},
      {"max_iterations", seeded.method == refine::CoreMethod::kIpopt
                             ? refine::ipoptMaxIterations(seeded)
                             : seeded.parametric.max_iterations},
      {"time_limit_s",
       seeded.time_limit_s ? nlohmann::json(*seeded.time_limit_s) : nlohmann::json(nullptr)},
      {"solve_time_ms", solution.total_time_ms},
      // The clock ended the solve (or its best attempt) before it finished: more time may help.
      {"time_limit_reached", solution.time_limit_reached},
      {"seed_time_s", seeded.seed_time_s},
      {"first_seed_time_s", refine::firstSeedBudget(seeded)},
      {"search_improve_milestones", seeded.search_improve_milestones},
      {"search_improvements", seeded.search_improvements},
      {"tolerance",
       {{"position_m", seeded.parametric.criteria.position_m},
        {"heading_rad", seeded.parametric.criteria.heading_rad},
        {"lagrangian_gradient", seeded.parametric.criteria.lagrangian_gradient}}},
      {"attempts", attemptsJson(solution.attempts)},
      {"history", iterationHistoryJson(solution.history, solution.parametric.has_value())},
  };
  if (solution.reachability) {
    json["reachability"] = {{"reachable", solution.reachability->reachable},
                            {"decided", solution.reachability->decided},
                            {"states_visited", solution.reachability->states_visited},
                            {"cells_reached", solution.reachability->cells_reached},
                            {"attitude_samples", solution.reachability->attitude_samples},
                            {"time_ms", solution.reachability->time_ms}};
    const auto trap = [](const std::optional<models::CurvatureTrap>& t) {
      if (!t) return nlohmann::json(nullptr);
      static const char* const kOutcomes[] = {"trapped", "escapes", "reaches_other_end",
                                              "undecided"};
      return nlohmann::json{{"outcome", kOutcomes[static_cast<int>(t->outcome)]},
                            {"level", t->level},
                            {"boxes_settled", t->boxes_settled},
                            {"attitude_samples", t->attitude_samples},
                            {"radius_m", t->radius_m},
                            {"area_m2", t->area_m2},
                            {"time_ms", t->time_ms}};
    };
    json["reachability"]["curvature"] = {{"goal", trap(solution.reachability->goal_trap)},
                                         {"start", trap(solution.reachability->start_trap)}};
  }
  if (solution.parametric) {
    const ocp::SolveResult& s = solution.parametric->solver;
    json["solver_time_ms"] = s.solve_time_ms;
    json["integrations"] = s.integrations + solution.parametric->initial_guess.integrations;
    json["controls"] = std::vector<double>(s.q.data(), s.q.data() + s.q.size());
    if (solution.parametric->path_points > 0) {
      // ipopt: the path points of the last solve, and their cap.
      json["path_points"] = solution.parametric->path_points;
      json["max_path_points"] = seeded.parametric.max_path_points;
    }
  }
  if (solution.transcription) {
    const ocp::VerifiedTranscription& t = *solution.transcription;
    const ocp::TranscriptionSolution& x = t.solution;
    nlohmann::json active = nlohmann::json::array();
    for (const ocp::ActiveConstraint& a : x.active) {
      active.push_back({{"limit", a.name},
                        {"t", a.t},
                        {"point", a.point},
                        {"value", a.value},
                        {"multiplier", a.multiplier}});
    }
    nlohmann::json rounds = nlohmann::json::array();
    for (const ocp::TranscriptionRound& r : t.rounds) {
      rounds.push_back({{"intervals", r.intervals},
                        {"speed_margin", r.speed_margin},
                        {"limit_margin", r.limit_margin},
                        {"clearance_m", r.clearance_m},
                        {"status", ocp::solveStatusName(r.status)},
                        {"reason", r.reason},
                        {"iterations", r.iterations}});
    }
    json["scheme"] = ocp::transcriptionSchemeName(x.scheme);
    json["intervals"] = x.mesh.empty() ? 0 : static_cast<int>(x.mesh.size()) - 1;
    json["max_intervals"] = seeded.transcription.max_intervals;
    json["ipopt_status"] = x.ipopt_status;
    json["solver_cost"] = jsonNumber(x.result.cost);
    json["max_defect"] = jsonNumber(x.max_defect);
    json["active_constraints"] = active;
    json["verification_rounds"] = rounds;
  }
  json.update(verifiedTrajectoryJson(solution.verified));
  json.update(verdictJson(solution.verdict, solution.verified.ok));
  return json;
}

}  // namespace

int runSolve(const SolveOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  if (options.method) {
    const std::optional<SolverMethod> method = parseSolverMethod(*options.method);
    if (!method) throw InputError("--method: unknown method '" + *options.method + "'");
    problem.solver.method = *method;
  }
  if (isTranscriptionMethod(problem.solver.method)) (void)transcriptionOptions(problem);
  if (options.guess && problem.solver.method != SolverMethod::kShooting &&
      problem.solver.method != SolverMethod::kCollocation) {
    throw InputError("--guess: only shooting and collocation take an initial guess");
  }
  // Every output is checked before the work starts.
  if (options.out) ensureWritableFile(*options.out, "--out");
  if (options.plot) ensureWritableFile(*options.plot, "--plot");
  const ProblemScene scene(problem, context);
  const terrain::ElevationMap& map = scene.map();
  const models::TerrainFollowingModel& vehicle = scene.vehicle();
  const ocp::BoundaryValueProblem bvp = boundaryValueProblem(problem, scene);
  std::optional<terrain::ClearanceMap> clearance;
  if (problem.solver.min_clearance_m) clearance.emplace(map);
  refine::SeededSolveOptions seeded =
      seededSolveOptions(problem, clearance ? &*clearance : nullptr, context.stop);
  seeded.on_attempt = [&context](const refine::SeedAttempt& a) {
    context.log->info("{} from {}: {} ({:.0f} ms; seed budget {:.3g} s, round {})", a.method,
                      a.seed, ocp::solveStatusName(a.status), a.time_ms, a.budget_s, a.round);
  };
  refine::SeededSolution solution;
  if (options.guess) {
    // A user's guess: the transcription from it alone.
    const models::Trajectory candidate = models::readTrajectoryCsv(*options.guess);
    const Expected<ocp::TranscriptionGuess> guess = ocp::guessFromCandidate(candidate, bvp);
    if (!guess) throw InputError(options.guess->string() + ": " + guess.reason());
    ocp::TranscriptionSolveOptions solve = seeded.transcription;
    solve.criteria = seeded.parametric.criteria;
    solve.map = &map;
    solve.stop = context.stop;
    solve.time_limit_s = seeded.time_limit_s;
    if (problem.solver.method == SolverMethod::kShooting) {
      solve.transcription.scheme = ocp::TranscriptionScheme::kMultipleShooting;
    }
    if (solve.transcription.intervals <= 0) solve.transcription.intervals = 40;
    solve.max_intervals = std::max(solve.max_intervals, solve.transcription.intervals);
    solution =
        refine::seededSolutionOf(ocp::solveTranscription(vehicle, bvp, *guess, solve),
                                 solverMethodName(problem.solver.method), options.guess->string());
  } else {
    context.log->info(
        "solving with {} ({} seeds) on the {} model", solverMethodName(problem.solver.method),
        problem.solver.initial_guess == InitialGuessKind::kFlat ? "004's flat" : "global",
        models::vehicleModelName(problem.vehicle.model));
    solution = refine::solveSeeded(vehicle, bvp, &map, seeded);
  }
  if (options.out && solution.verified.ok) {
    models::writeTrajectoryCsv(solution.verified.trajectory, *options.out,
                               scene.platformPitchResponse());
  }
  nlohmann::json report = seededReportJson(solution, seeded, problem);
  if (options.plot) {
    report["plots"] = plotSolve(options, problem, scene, solution.verified, solution.history,
                                solution.method, context);
  }
  if (context.stopRequested()) report["stopped_by"] = "interrupt";
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << ocp::solveStatusName(solution.status) << " (" << solution.method << " from "
                << solution.initial_guess << ", " << solution.iterations << " iterations, "
                << solution.total_time_ms << " ms)";
    if (!solution.reason.empty()) context.out << ": " << solution.reason;
    context.out << '\n';
    printVerifiedTrajectory(context.out, solution.verified);
    if (options.out && solution.verified.ok) {
      context.out << "  trajectory  " << options.out->string() << '\n';
    }
  }
  return solution.status == ocp::SolveStatus::kConverged ? kExitSuccess : kExitNotSolved;
}

}  // namespace terratraj::apps
