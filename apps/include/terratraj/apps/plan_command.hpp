#pragma once
// `terratraj plan`: global planning from the problem's start to its goal region with the
// kinodynamic PRM (search::KinodynamicPrm, 001_...), the state lattice (A* / ARA*) or the
// topology-aware lattice (TAEASL, 002_...); the contract's JSON report and every solution as CSV
// (`<out-dir>/solution_<k>.csv`, best first; one per homotopy class for taeasl).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/apps/verdict_json.hpp"
#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::apps {

/// Options of `terratraj plan`.
struct PlanOptions {
  std::filesystem::path problem;
  std::optional<std::string> planner;                ///< overrides planner.kind
  std::optional<double> time_limit_s;                ///< overrides planner.time_limit_s [s], >= 0
  std::optional<std::uint64_t> seed;                 ///< overrides planner.seed
  std::filesystem::path out_dir = "terratraj-plan";  ///< where solution_0.csv goes
  /// Refine every solution (refine::CandidateRefiner) into `<out-dir>/refined_<k>.csv`.
  bool refine = false;
  std::optional<std::string> method;          ///< overrides refine.method
  std::optional<std::filesystem::path> plot;  ///< map PNG (and -profiles, -convergence)
};

class ProblemScene;

/// For the lattice planners: throws InputError naming the tolerance key when no lattice
/// position or heading lies in the goal region (planner.lattice_resolution_m, heading_count)
/// of `query` (planningProblem()).
void checkLatticeGoal(const ProblemSpec& problem, const search::PlanningProblem& query);

/// A finished `plan` run: its report and exit status.
struct PlanRun {
  nlohmann::json report;
  int exit_status = 0;
  /// A few lines a person reads (what the text mode prints).
  std::string summary;
};

/// `plan` on a problem already read (overrides applied): plans, writes the solutions, refines
/// them with --refine, draws the plots with --plot. Exit status 0 when solved (and, with
/// --refine, at least one refinement converged), 1 otherwise; InputError for bad input.
PlanRun executePlan(const ProblemSpec& problem, const PlanOptions& options,
                    CommandContext& context);

/// What a report says about its run besides the planner's result.
struct PlanReportInfo {
  std::string planner = "prm";
  double time_limit_s = 0.0;
  std::uint64_t seed = 1;
  std::vector<std::filesystem::path> files;         ///< each solution's CSV, when written
  std::vector<search::CheckReport> checks;          ///< each solution's independent re-check
  nlohmann::json extra = nlohmann::json::object();  ///< more top-level keys (lattice, frames)
};

/// The contract's plan report (status, planner, time_limit_s, first_solution_ms,
/// planning_time_ms, nodes, trapped_fraction, solutions[{cost_s, length_m, homotopy, file}])
/// plus: seed, reason, best_cost_s, first_solution_cost_s, statistics, cost_history
/// [{time_ms, cost_s}], constraint_violation and violated_limits (from the re-check).
nlohmann::json planReportJson(const search::PlanResult& result, const PlanReportInfo& info);

/// Runs the command: exit 0 solved, 1 no solution (the report still printed), InputError
/// (exit 2) for bad input: an unreadable problem, a negative time limit, start or goal off the
/// map, on lethal or no-data cells, at an attitude beyond the limits, or a start turning in
/// place; for the lattice planners also a missing or inconsistent primitive file, a goal
/// region holding no lattice state, a start with non-zero curvature.
int runPlan(const PlanOptions& options, CommandContext& context);

/// Options of `terratraj primitives`.
struct PrimitivesOptions {
  std::filesystem::path problem;
  std::filesystem::path out;  ///< the primitive file to write
};

/// Generates the primitives of the problem's lattice for its vehicle limits (never from the
/// cache) and writes them to `out`. Exit 0, or InputError (exit 2) for bad input or when a
/// heading gets no primitive (the failures listed).
int runPrimitives(const PrimitivesOptions& options, CommandContext& context);

}  // namespace terratraj::apps
