#include "terratraj/apps/refine_command.hpp"

#include <cmath>
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
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {

using bench::jsonNumber;

nlohmann::json refineReportJson(const refine::RefinementResult& r,
                                const refine::RefinementOptions& options,
                                const std::filesystem::path& candidate_file,
                                const std::optional<std::filesystem::path>& out) {
  const nlohmann::json history = iterationHistoryJson(r.history, false);
  nlohmann::json derived = nlohmann::json::array();
  for (const std::string& c : r.derived_columns) derived.push_back(c);
  nlohmann::json candidate{{"file", candidate_file.string()},
                           {"samples", r.candidate.samples.size()},
                           {"derived_columns", derived}};
  if (r.candidate_figures) candidate.update(trajectoryFiguresJson(*r.candidate_figures));
  const bool transcription =
      r.method == refine::RefineMethod::kCollocation || r.method == refine::RefineMethod::kShooting;
  nlohmann::json json{
      {"status", ocp::solveStatusName(r.status)},
      {"reason", r.reason},
      {"method", refine::refineMethodName(r.method)},
      {"method_rule", r.method_rule},
      {"iterations", r.iterations},
      {"max_iterations",
       transcription ? options.transcription.max_iterations : options.parametric.max_iterations},
      {"time_limit_s",
       options.time_limit_s ? nlohmann::json(*options.time_limit_s) : nlohmann::json(nullptr)},
      {"solve_time_ms", r.solve_time_ms},
      {"time_limit_reached", r.time_limit_reached},
      {"intervals", r.intervals},
      {"clearance_constraint_m", r.clearance_used_m},
      {"corridor_radius_m", r.corridor_radius_m},
      {"guess_shortcut_m", r.guess_shortcut_m},
      {"guess_retimed_s", r.guess_retimed_s},
      {"barrier", r.warm_start ? "warm" : "adaptive"},
      {"coarse",
       {{"intervals", r.coarse_intervals},
        {"iterations", r.coarse_iterations},
        {"limit_excess", r.coarse_limit_excess},
        {"used", r.coarse_used},
        {"status", r.coarse_intervals > 0 ? nlohmann::json(ocp::solveStatusName(r.coarse_status))
                                          : nlohmann::json(nullptr)}}},
      {"margins",
       {{"rounds", r.margin_rounds},
        {"speed", r.speed_margin_used},
        {"limits", r.limit_margin_used}}},
      {"history", history},
      {"candidate", candidate},
      {"refined",
       r.refined_figures ? trajectoryFiguresJson(*r.refined_figures) : nlohmann::json(nullptr)},
      {"homotopy",
       {{"before", r.candidate_figures ? nlohmann::json(r.candidate_figures->homotopy)
                                       : nlohmann::json(nullptr)},
        {"after",
         r.refined_figures ? nlohmann::json(r.refined_figures->homotopy) : nlohmann::json(nullptr)},
        {"kept", r.homotopy_kept}}},
      {"cost_ratio", jsonNumber(r.costRatio())},
      {"file", out ? nlohmann::json(out->string()) : nlohmann::json(nullptr)},
      {"returned", r.returned_candidate ? "candidate"
                   : r.verified.ok      ? "refined"
                                        : "nothing"},
  };
  json.update(verifiedTrajectoryJson(r.verified));
  json.update(verdictJson(r.verdict, r.refined_figures.has_value()));
  return json;
}

namespace {

// The trajectory a refinement returns: the refined one, or the candidate when the refinement
// ended worse than it (null when neither exists).
const models::Trajectory* returnedTrajectory(const refine::RefinementResult& r) {
  if (r.returned_candidate) return &r.candidate;
  return r.verified.ok ? &r.verified.trajectory : nullptr;
}

void printRefineSummary(const refine::RefinementResult& result,
                        const std::optional<std::filesystem::path>& written,
                        CommandContext& context) {
  context.out << ocp::solveStatusName(result.status) << " ("
              << refine::refineMethodName(result.method) << ", " << result.iterations
              << " iterations, " << result.solve_time_ms << " ms)";
  if (!result.reason.empty()) context.out << ": " << result.reason;
  context.out << '\n';
  if (!result.method_rule.empty()) context.out << "  method      " << result.method_rule << '\n';
  const auto line = [&](const char* name, const refine::TrajectoryFigures& f) {
    context.out << "  " << name << "cost " << f.cost << ", duration " << f.duration_s << " s, "
                << f.length_m << " m, max |pitch| " << f.max_abs_pitch << " rad, max |roll| "
                << f.max_abs_roll << " rad, class '" << f.homotopy << "', re-check "
                << (f.check.ok() ? "ok" : "VIOLATED") << '\n';
  };
  if (result.candidate_figures) line("candidate   ", *result.candidate_figures);
  if (result.refined_figures) line("refined     ", *result.refined_figures);
  if (std::isfinite(result.costRatio())) {
    context.out << "  ratio       " << result.costRatio() << " (refined / candidate cost)\n";
  }
  if (written) {
    context.out << "  trajectory  " << written->string()
                << (result.returned_candidate ? " (the candidate)" : "") << '\n';
  }
}

}  // namespace

int runRefine(const RefineOptions& options, CommandContext& context) {
  ProblemSpec problem = loadProblem(options.problem);
  refine::RefinementOptions refine = refinementOptions(problem, options.method);
  refine.stop = context.stop;
  const models::Trajectory candidate = models::readTrajectoryCsv(options.candidate);
  // Every output is checked before the work starts.
  if (options.out) ensureWritableFile(*options.out, "--out");
  if (options.plot) ensureWritableFile(*options.plot, "--plot");
  const ProblemScene scene(problem, context);
  const search::PlanningProblem query = planningProblem(problem, scene);
  const ocp::BoundaryValueProblem bvp = boundaryValueProblem(problem, scene);
  const search::ReferenceFrames frames = problemReferenceFrames(problem, query);
  const refine::CandidateRefiner refiner(query, bvp, frames, refine);
  context.log->info("refining {} ({} samples) on the {} model", options.candidate.string(),
                    candidate.samples.size(), models::vehicleModelName(problem.vehicle.model));
  const refine::RefinementResult result = refiner.refine(candidate);
  const models::Trajectory* returned = returnedTrajectory(result);
  std::optional<std::filesystem::path> written;
  if (options.out && returned != nullptr) {
    models::writeTrajectoryCsv(*returned, *options.out, scene.platformPitchResponse());
    written = *options.out;
  }
  nlohmann::json report = refineReportJson(result, refine, options.candidate, written);
  // A candidate that cannot be used is bad input: the report still says what was measured.
  const bool bad_candidate = result.status == ocp::SolveStatus::kError;
  if (bad_candidate) {
    report["error"] = options.candidate.string() + ": " + result.reason;
    context.err << "terratraj: error: " << options.candidate.string() << ": " << result.reason
                << '\n';
  }
  if (context.stopRequested()) report["stopped_by"] = "interrupt";
  if (options.plot && !bad_candidate) {
    PlotRequest plot;
    plot.title = "refine " + options.candidate.filename().string() + " (" +
                 refine::refineMethodName(result.method) + ")";
    plot.limits = problem.vehicle.limits;
    plot.start = PlotPose{scene.start().x, scene.start().y, scene.start().heading};
    plot.goal = PlotPose{scene.goal().x, scene.goal().y, scene.goal().heading};
    plot.tolerance_position_m = refine.parametric.criteria.position_m;
    const std::filesystem::path derived =
        options.plot->parent_path() / (options.plot->stem().string() + "-candidate.csv");
    models::writeTrajectoryCsv(result.candidate, derived, scene.platformPitchResponse());
    plot.trajectories.push_back({"candidate", derived, true, 0});
    if (result.verified.ok) {
      // The refined trajectory: --out when it holds it, else a file beside the plot.
      std::filesystem::path refined;
      if (written && !result.returned_candidate) {
        refined = *written;
      } else {
        refined = options.plot->parent_path() / (options.plot->stem().string() + "-refined.csv");
        models::writeTrajectoryCsv(result.verified.trajectory, refined,
                                   scene.platformPitchResponse());
      }
      plot.trajectories.push_back({"refined", refined, false, 0});
    }
    plot.histories.push_back({refine::refineMethodName(result.method), result.history, 0});
    plot.frames = plotFrames(frames);
    report["plots"] = writePlots(plot, scene.map(), *options.plot, context).toJson();
  }
  if (written) {
    const std::filesystem::path report_file = written->parent_path() / "report.json";
    nlohmann::json saved = report;
    saved["version"] = kTerratrajVersion;
    saved["command"] = "refine";
    saved["problem"] = problemJson(problem, scene);
    writeJsonFile(saved, report_file);
    report["report_file"] = report_file.string();
  }
  if (context.json) {
    context.out << report.dump(2) << '\n';
  } else {
    printRefineSummary(result, written, context);
  }
  if (bad_candidate) return kExitBadInput;
  return result.status == ocp::SolveStatus::kConverged ? kExitSuccess : kExitNotSolved;
}

}  // namespace terratraj::apps
