#pragma once
// `terratraj refine` and the refinement half of `terratraj plan --refine`: candidates (a
// planner's, or any path or trajectory CSV) turned into locally optimal trajectories by
// refine::CandidateRefiner, with reports that put each candidate beside its refinement
// (docs/refinement.md).

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/reference_frames.hpp"

namespace terratraj::apps {

/// Options of `terratraj refine`.
struct RefineOptions {
  std::filesystem::path problem;
  std::filesystem::path candidate;            ///< the candidate CSV (t,x,y,... or only x,y)
  std::optional<std::string> method;          ///< overrides refine.method
  std::optional<std::filesystem::path> out;   ///< the refined trajectory (CSV)
  std::optional<std::filesystem::path> plot;  ///< map PNG (and -profiles, -convergence)
};

/// The `refine` report: the contract's solve/refine keys (from the independent re-simulation)
/// plus candidate {file, derived_columns, figures}, refined {figures}, homotopy {before, after,
/// kept}, cost_ratio and the settings in use.
nlohmann::json refineReportJson(const refine::RefinementResult& result,
                                const refine::RefinementOptions& options,
                                const std::filesystem::path& candidate_file,
                                const std::optional<std::filesystem::path>& out);

/// Runs the command: exit 0 when the refinement converged (solver, re-simulation, limits and
/// class all hold), 1 when it did not (the report still printed with the status and reason),
/// InputError (exit 2) for bad input: an unreadable problem or candidate CSV, a candidate
/// without x, y, with NaN, a single point, or leaving the map (the JSON report then also
/// holds what could be measured of the candidate).
int runRefine(const RefineOptions& options, CommandContext& context);

}  // namespace terratraj::apps
