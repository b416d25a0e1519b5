#include "terratraj/apps/plan_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>

#include "message_number.hpp"
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
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/plan_verdict.hpp"
#include "terratraj/search/primitive_file.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::apps {

using bench::jsonNumber;

void checkLatticeGoal(const ProblemSpec& problem, const search::PlanningProblem& query) {
  search::LatticeSpec lattice;
  lattice.resolution = latticeResolution(problem, query.map->geometry());
  lattice.heading_count = problem.planner.heading_count;
  const Eigen::Vector2d& start = query.start.position;
  const Eigen::Vector2d& goal = query.goal.position;
  const double goal_heading = query.goal.heading;
  const Eigen::Vector2d cells = (goal - start) / lattice.resolution;
  const Eigen::Vector2d nearest =
      start + lattice.resolution * Eigen::Vector2d(std::round(cells.x()), std::round(cells.y()));
  const double position_tolerance = query.goal.position_tolerance;
  if ((nearest - goal).norm() > position_tolerance) {
    throw InputError(problem.source_file.string() + ": planner.goal_position_tolerance_m: " +
                     formatNumber(position_tolerance) + " m holds no lattice position (spacing " +
                     formatNumber(lattice.resolution) + " m from the start): use at least " +
                     formatNumber(std::ceil(lattice.resolution * std::sqrt(0.5) * 100.0) / 100.0) +
                     " m");
  }
  const double heading_tolerance = problem.planner.goal_heading_tolerance;
  const double heading_gap = std::abs(
      search::wrapAngle(goal_heading - lattice.headingAngle(lattice.nearestHeading(goal_heading))));
  if (heading_gap > heading_tolerance) {
    throw InputError(problem.source_file.string() +
                     ": planner.goal_heading_tolerance: " + formatNumber(heading_tolerance) +
                     " rad holds no lattice heading (" + std::to_string(lattice.heading_count) +
                     " headings): use at least " + formatNumber(heading_gap) + " rad");
  }
}

namespace {

// Writes every solution (each passed the verdict in the planner) and fills the report's info.
void writeSolutions(const search::PlanResult& result, const std::filesystem::path& out_dir,
                    const models::SegwayPitchResponse* platform, PlanReportInfo& info) {
  for (std::size_t k = 0; k < result.solutions.size(); ++k) {
    const std::filesystem::path file = out_dir / ("solution_" + std::to_string(k) + ".csv");
    models::writeTrajectoryCsv(result.solutions[k].trajectory, file, platform);
    info.files.push_back(file);
    info.checks.push_back(result.solutions[k].check);
  }
}

// The planner's time limit, iteration budget (planner.max_iterations) and the SIGINT flag.
search::TerminationCondition planTermination(const ProblemSpec& problem, CommandContext& context) {
  search::TerminationCondition termination =
      search::TerminationCondition::timeLimit(planningTimeLimit(problem));
  if (problem.planner.max_iterations) {
    termination.maxIterations(static_cast<std::size_t>(*problem.planner.max_iterations));
  }
  termination.stopFlag(context.stop);
  return termination;
}

// A progress line per solved heading of the primitive generation (seconds to minutes).
std::function<void(int, int)> primitiveProgress(CommandContext& context) {
  return [&context](int done, int total) {
    context.log->info("motion primitives: solving heading {} of {}", done + 1, total);
  };
}

// A planner with what it plans on (the lattice planners' primitives and graph), kept alive
// together.
struct PlannerSetup {
  std::unique_ptr<search::LoadedPrimitives> primitives;
  std::unique_ptr<search::LatticeGraph> graph;
  std::unique_ptr<search::Planner> planner;
};

// The lattice planners: primitives (file, cache or generated), graph, A* / ARA* or TAEASL (on
// the run's reference `frames`); their settings into the report's `lattice` / `taeasl` sections.
PlannerSetup setUpLatticePlanner(const ProblemSpec& problem, const search::PlanningProblem& query,
                                 const search::ReferenceFrames& frames, PlanReportInfo& info,
                                 CommandContext& context) {
  PlannerSetup setup;
  search::LatticeSpec lattice;
  lattice.resolution = latticeResolution(problem, query.map->geometry());
  lattice.heading_count = problem.planner.heading_count;
  search::PrimitiveGenerationOptions generation;
  if (problem.planner.primitive_speed) generation.speed = *problem.planner.primitive_speed;
  generation.progress = primitiveProgress(context);
  generation.stop = context.stop;
  const auto load_started = std::chrono::steady_clock::now();
  const std::filesystem::path cache_dir = primitiveCacheDirectory();
  setup.primitives = std::make_unique<search::LoadedPrimitives>(search::loadOrGeneratePrimitives(
      lattice, query.limits, generation,
      problem.planner.primitives ? *problem.planner.primitives : std::filesystem::path(),
      cache_dir));
  const search::LoadedPrimitives& primitives = *setup.primitives;
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_started)
          .count();
  if (!primitives.cache_note.empty()) {
    context.log->info("primitives: {}{}", primitives.cache_note,
                      cache_dir.empty() && !problem.planner.primitives
                          ? " (set TERRATRAJ_CACHE_DIR, XDG_CACHE_HOME or HOME to keep them)"
                          : "");
  }
  context.log->info("{} motion primitives ({}{}{}), {} ms", primitives.set.size(),
                    search::primitiveSourceName(primitives.source),
                    primitives.path.empty() ? "" : " ", primitives.path.string(), load_ms);

  search::LatticeGraphOptions graph_options;
  if (problem.cost.kind == CostKind::kSlopeDwell) {
    graph_options.slope_dwell_alpha = problem.cost.alpha;
  }
  setup.graph = std::make_unique<search::LatticeGraph>(query, primitives.set, graph_options);
  const search::LatticeGraph& graph = *setup.graph;
  if (graph.error()) throw InputError(problem.source_file.string() + ": " + *graph.error());
  checkLatticeGoal(problem, query);
  info.extra["lattice"] = {
      {"resolution_m", lattice.resolution},
      {"heading_count", lattice.heading_count},
      {"sample_spacing_m", graph.sampleSpacing()},
      {"start_connectors", graph.connectorCount()},
      {"primitives",
       {{"count", primitives.set.size()},
        {"source", search::primitiveSourceName(primitives.source)},
        {"file", primitives.path.empty() ? nlohmann::json(nullptr)
                                         : nlohmann::json(primitives.path.string())},
        {"generation_speed", primitives.set.generation.speed},
        {"load_ms", load_ms}}}};

  if (problem.planner.kind == PlannerKind::kLattice) {
    const search::LatticePlannerOptions options = latticePlannerOptions(problem);
    info.extra["lattice"]["algorithm"] = search::latticeAlgorithmName(options.algorithm);
    info.extra["lattice"]["initial_epsilon"] = options.initial_epsilon;
    info.extra["lattice"]["epsilon_step"] = options.epsilon_step;
    context.log->info("planning with the lattice ({}) for {} s",
                      search::latticeAlgorithmName(options.algorithm), planningTimeLimit(problem));
    setup.planner = std::make_unique<search::LatticePlanner>(graph, options);
    return setup;
  }
  const search::TaeaslOptions options = taeaslOptions(problem);
  auto taeasl = std::make_unique<search::TaeaslPlanner>(graph, frames, options);
  const search::TaeaslPlanner& planner = *taeasl;
  nlohmann::json frames_json = nlohmann::json::array();
  for (std::size_t k = 0; k < planner.frames().size(); ++k) {
    const search::ReferenceFrame& f = planner.frames().frames()[k];
    frames_json.push_back({{"name", search::HomotopySignature::frameName(static_cast<int>(k))},
                           {"cluster", f.cluster},
                           {"start", {f.start.x(), f.start.y()}},
                           {"end", {f.end.x(), f.end.y()}}});
  }
  info.extra["taeasl"] = {{"homotopy_classes", options.homotopy_classes},
                          {"frame_radius_m", options.frame_radius},
                          {"frame_anchor", search::frameAnchorName(options.anchor)},
                          {"anchor", {planner.anchorPosition().x(), planner.anchorPosition().y()}},
                          {"heuristic_weight", options.heuristic_weight},
                          {"max_signature_length", planner.maxSignatureLength()},
                          {"frames", frames_json}};
  context.log->info("planning with TAEASL for {} s ({} reference frames)",
                    planningTimeLimit(problem), planner.frames().size());
  setup.planner = std::move(taeasl);
  return setup;
}

// The problem's planner, ready to solve (TAEASL on the run's reference `frames`).
PlannerSetup setUpPlanner(const ProblemSpec& problem, const search::PlanningProblem& query,
                          const search::ReferenceFrames& frames, PlanReportInfo& info,
                          CommandContext& context) {
  if (problem.planner.kind != PlannerKind::kPrm) {
    return setUpLatticePlanner(problem, query, frames, info, context);
  }
  PlannerSetup setup;
  search::PrmOptions prm;
  prm.seed = problem.planner.seed;
  setup.planner = std::make_unique<search::KinodynamicPrm>(query, prm);
  context.log->info("planning with prm for {} s (seed {}, {} model)", planningTimeLimit(problem),
                    prm.seed, query.vehicle->name());
  return setup;
}

}  // namespace

namespace {

// The candidates of a plan: every solution.
std::vector<const models::Trajectory*> candidatesOf(const search::PlanResult& result) {
  std::vector<const models::Trajectory*> candidates;
  for (const search::PlanSolution& s : result.solutions) candidates.push_back(&s.trajectory);
  return candidates;
}

// The refinement of every candidate, written to refined_<k>.csv, into the report.
struct RefinedCandidates {
  std::vector<refine::RefinementResult> results;
  std::vector<std::optional<std::filesystem::path>> files;
  int converged = 0;
};

RefinedCandidates refineCandidates(const ProblemSpec& problem, const ProblemScene& scene,
                                   const search::PlanningProblem& query,
                                   const search::ReferenceFrames& frames,
                                   const refine::RefinementOptions& settings,
                                   const search::PlanResult& result, const PlanOptions& options,
                                   nlohmann::json& report, CommandContext& context) {
  RefinedCandidates refined;
  const ocp::BoundaryValueProblem bvp = boundaryValueProblem(problem, scene);
  const refine::CandidateRefiner refiner(query, bvp, frames, settings);
  const std::vector<const models::Trajectory*> candidates = candidatesOf(result);
  double ratio_sum = 0.0;
  int ratios = 0, kept = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (context.stopRequested()) break;
    context.log->info("refining solution {} of {} ({} samples)", k + 1, candidates.size(),
                      candidates[k]->samples.size());
    refine::RefinementResult r = refiner.refine(*candidates[k]);
    std::optional<std::filesystem::path> file;
    if (r.returned_candidate) {
      file = options.out_dir / ("solution_" + std::to_string(k) + ".csv");
    } else if (r.verified.ok) {
      file = options.out_dir / ("refined_" + std::to_string(k) + ".csv");
      models::writeTrajectoryCsv(r.verified.trajectory, *file, scene.platformPitchResponse());
    }
    context.log->info("solution {}: {} ({}, {} ms){}{}", k, ocp::solveStatusName(r.status),
                      refine::refineMethodName(r.method), r.solve_time_ms,
                      r.reason.empty() ? "" : ": ", r.reason);
    nlohmann::json& solution = report["solutions"][k];
    if (r.candidate_figures) {
      solution["cost"] = r.candidate_figures->cost;
      solution["max_abs_pitch_rad"] = r.candidate_figures->max_abs_pitch;
      solution["max_abs_roll_rad"] = r.candidate_figures->max_abs_roll;
      solution["min_clearance_m"] = jsonNumber(r.candidate_figures->min_clearance_m);
      solution["homotopy_frames"] = r.candidate_figures->homotopy;
    }
    solution["refined"] = refinedSolutionJson(r, file);
    if (r.status == ocp::SolveStatus::kConverged) ++refined.converged;
    if (r.homotopy_kept) ++kept;
    if (std::isfinite(r.costRatio()) && r.status == ocp::SolveStatus::kConverged) {
      ratio_sum += r.costRatio();
      ++ratios;
    }
    refined.results.push_back(std::move(r));
    refined.files.push_back(file);
  }
  report["refine"] = {
      {"method", refine::refineMethodName(settings.method)},
      {"interval_length_m", settings.interval_length_m},
      {"min_intervals", settings.min_intervals},
      {"max_intervals", settings.max_intervals},
      {"min_clearance_m", settings.min_clearance_m},
      {"max_iterations", settings.transcription.max_iterations},
      {"time_limit_s",
       settings.time_limit_s ? nlohmann::json(*settings.time_limit_s) : nlohmann::json(nullptr)},
      {"candidates", candidates.size()},
      {"converged", refined.converged},
      {"homotopy_kept", kept},
      {"mean_cost_ratio",
       ratios > 0 ? nlohmann::json(ratio_sum / ratios) : nlohmann::json(nullptr)},
  };
  return refined;
}

// The figures of a plan (and its refinements).
PlotOutcome plotPlan(const ProblemSpec& problem, const ProblemScene& scene,
                     const search::ReferenceFrames& frames, const search::PlanResult& result,
                     const PlanReportInfo& info, const RefinedCandidates* refined,
                     const std::filesystem::path& png, CommandContext& context) {
  PlotRequest plot;
  plot.title = std::string("plan (") + info.planner + ")" + (refined ? " and refine" : "");
  plot.limits = problem.vehicle.limits;
  plot.start = PlotPose{scene.start().x, scene.start().y, scene.start().heading};
  plot.goal = PlotPose{scene.goal().x, scene.goal().y, scene.goal().heading};
  plot.tolerance_position_m = problem.solver.tolerance_position_m;
  for (std::size_t k = 0; k < info.files.size(); ++k) {
    std::string label = "candidate " + std::to_string(k);
    if (k < result.solutions.size() && !result.solutions[k].homotopy.empty()) {
      label += " '" + result.solutions[k].homotopy + "'";
    }
    plot.trajectories.push_back({label, info.files[k], refined != nullptr, static_cast<int>(k)});
  }
  if (refined) {
    for (std::size_t k = 0; k < refined->results.size(); ++k) {
      const refine::RefinementResult& r = refined->results[k];
      if (refined->files[k]) {
        plot.trajectories.push_back(
            {"refined " + std::to_string(k) + " (" + ocp::solveStatusName(r.status) + ")",
             *refined->files[k], false, static_cast<int>(k)});
      }
      plot.histories.push_back(
          {"refine " + std::to_string(k) + " (" + refine::refineMethodName(r.method) + ")",
           r.history, static_cast<int>(k)});
    }
  }
  plot.frames = plotFrames(frames);
  return writePlots(plot, scene.map(), png, context);
}

std::string planSummary(const search::PlanResult& result, const PlanReportInfo& info,
                        const RefinedCandidates* refined) {
  std::ostringstream out;
  out << search::planStatusName(result.status) << " (" << info.planner << ", "
      << result.planning_time_ms << " ms, " << result.nodes << " nodes)";
  if (!result.reason.empty()) out << ": " << result.reason;
  out << '\n';
  for (const search::RejectedSolution& r : result.rejected) {
    out << "  rejected        duration " << r.cost_s << " s"
        << (r.homotopy.empty() ? "" : ", class " + r.homotopy) << ": " << r.reason << '\n';
  }
  if (result.status != search::PlanStatus::kSolved) return out.str();
  out << "  first solution  " << *result.first_solution_ms << " ms, cost "
      << result.first_solution_cost_s << " s\n";
  for (std::size_t k = 0; k < info.files.size(); ++k) {
    const search::PlanSolution& solution = result.solutions[k];
    out << "  solution " << k << "      duration " << solution.cost_s << " s, length "
        << solution.length_m << " m";
    if (!solution.homotopy.empty()) out << ", class " << solution.homotopy;
    out << ", re-check " << (info.checks[k].ok() ? "ok" : "VIOLATED") << ", "
        << info.files[k].string() << '\n';
    if (refined && k < refined->results.size()) {
      const refine::RefinementResult& r = refined->results[k];
      out << "    refined       " << ocp::solveStatusName(r.status) << " by "
          << refine::refineMethodName(r.method) << " in " << r.solve_time_ms << " ms";
      if (r.refined_figures) {
        out << ": cost " << r.refined_figures->cost << " (x" << r.costRatio()
            << " the candidate's), duration " << r.refined_figures->duration_s << " s, length "
            << r.refined_figures->length_m << " m, class '" << r.refined_figures->homotopy << "' "
            << (r.homotopy_kept ? "kept" : "CHANGED");
      }
      if (!r.reason.empty()) out << "; " << r.reason;
      if (refined->files[k]) out << ", " << refined->files[k]->string();
      out << '\n';
    }
  }
  return out.str();
}

}  // namespace

PlanRun executePlan(const ProblemSpec& problem, const PlanOptions& options,
                    CommandContext& context) {
  // Every output is checked before the work starts.
  ensureWritableFolder(options.out_dir, "--out-dir");
  if (options.plot) ensureWritableFile(*options.plot, "--plot");
  const ProblemScene scene(problem, context);
  const search::PlanningProblem query = planningProblem(problem, scene);
  // Bad refine settings fail before planning.
  std::optional<refine::RefinementOptions> settings;
  if (options.refine) {
    settings = refinementOptions(problem, options.method);
    settings->stop = context.stop;
    // The planner's solutions end anywhere in its goal region (on a coarse lattice it must be
    // wider than refine's 0.5 m): the refiner takes them from all of it.
    settings->endpoint_tolerance_m =
        std::max(settings->endpoint_tolerance_m, query.goal.position_tolerance);
  }

  // The reference frames (TAEASL's classes, the refinements' and the plot's), built once.
  const bool with_frames = problem.planner.kind == PlannerKind::kTaeasl || settings || options.plot;
  const search::ReferenceFrames frames =
      with_frames ? problemReferenceFrames(problem, query) : search::ReferenceFrames();

  PlanReportInfo info;
  info.planner = plannerKindName(problem.planner.kind);
  info.time_limit_s = planningTimeLimit(problem);
  info.seed = problem.planner.seed;
  search::PlanResult result;
  if (problem.planner.kind != PlannerKind::kPrm && query.goal.contains(query.start)) {
    // Nothing to drive: no lattice (nor its start connectors) is needed.
    search::planStartInGoal(query, result);
  } else {
    const PlannerSetup setup = setUpPlanner(problem, query, frames, info, context);
    result = setup.planner->solve(planTermination(problem, context));
  }
  writeSolutions(result, options.out_dir, scene.platformPitchResponse(), info);

  PlanRun run;
  run.report = planReportJson(result, info);
  std::optional<RefinedCandidates> refined;
  if (settings && result.status == search::PlanStatus::kSolved) {
    refined = refineCandidates(problem, scene, query, frames, *settings, result, options,
                               run.report, context);
  }
  if (options.plot) {
    run.report["plots"] = plotPlan(problem, scene, frames, result, info,
                                   refined ? &*refined : nullptr, *options.plot, context)
                              .toJson();
  }
  if (context.stopRequested()) run.report["stopped_by"] = "interrupt";
  run.summary = planSummary(result, info, refined ? &*refined : nullptr);
  const bool solved = result.status == search::PlanStatus::kSolved;
  run.exit_status = solved && (!refined || refined->converged > 0) ? kExitSuccess : kExitNotSolved;
  nlohmann::json saved = run.report;
  saved["version"] = kTerratrajVersion;
  saved["command"] = options.refine ? "plan --refine" : "plan";
  saved["problem"] = problemJson(problem, scene);
  const std::filesystem::path report_file = options.out_dir / "report.json";
  writeJsonFile(saved, report_file);
  run.report["report_file"] = report_file.string();
  return run;
}

int runPlan(const PlanOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  if (options.planner) {
    const std::optional<PlannerKind> kind = parsePlannerKind(*options.planner);
    if (!kind) throw InputError("--planner: unknown planner '" + *options.planner + "'");
    problem.planner.kind = *kind;
  }
  if (options.time_limit_s) {
    if (!std::isfinite(*options.time_limit_s) || *options.time_limit_s < 0.0) {
      throw InputError("--time-limit: must be a finite number >= 0 s (got " +
                       formatNumber(*options.time_limit_s) + ")");
    }
    problem.planner.time_limit_s = *options.time_limit_s;
  }
  if (options.seed) problem.planner.seed = *options.seed;
  const PlanRun run = executePlan(problem, options, context);
  if (context.json) {
    context.out << run.report.dump(2) << '\n';
  } else {
    context.out << run.summary;
  }
  return run.exit_status;
}

int runPrimitives(const PrimitivesOptions& options, CommandContext& context) {
  const ProblemSpec problem = loadProblem(options.problem);
  const terrain::ElevationMap map = terrain::loadTerrain(problem.terrain);
  search::LatticeSpec lattice;
  lattice.resolution = latticeResolution(problem, map.geometry());
  lattice.heading_count = problem.planner.heading_count;
  search::PrimitiveGenerationOptions generation;
  if (problem.planner.primitive_speed) generation.speed = *problem.planner.primitive_speed;
  generation.progress = primitiveProgress(context);
  generation.stop = context.stop;
  context.log->info("generating motion primitives: {} m lattice, {} headings", lattice.resolution,
                    lattice.heading_count);
  const search::PrimitiveGenerationResult result =
      search::generatePrimitives(lattice, problem.vehicle.limits, generation);
  if (const std::optional<std::string> error =
          result.set.checkAgainst(lattice, &problem.vehicle.limits)) {
    std::string message = "motion primitives: generation failed: " + *error;
    for (const std::string& f : result.failures) message += "; " + f;
    throw InputError(message);
  }
  search::writePrimitiveFile(result.set, options.out);
  const search::PrimitiveGenerationInfo& g = result.set.generation;
  nlohmann::json failures = nlohmann::json::array();
  for (const std::string& f : result.failures) failures.push_back(f);
  const nlohmann::json report{{"status", "ok"},
                              {"file", options.out.string()},
                              {"resolution_m", lattice.resolution},
                              {"heading_count", lattice.heading_count},
                              {"primitives", result.set.size()},
                              {"generation_speed", g.speed},
                              {"solves", g.solves},
                              {"failed_solves", g.failures},
                              {"generation_time_ms", g.generation_time_ms},
                              {"missing", failures}};
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    context.out << result.set.size() << " primitives (" << g.solves << " solves, " << g.failures
                << " failed) in " << g.generation_time_ms << " ms -> " << options.out.string()
                << '\n';
    for (const std::string& f : result.failures) context.out << "  missing: " << f << '\n';
  }
  return kExitSuccess;
}

}  // namespace terratraj::apps
