#pragma once
// `terratraj plan`: global planning from the problem's start to its goal region with the
// kinodynamic PRM (search::KinodynamicPrm, 001_...), the contract's JSON report and the best
// trajectory as CSV (`<out-dir>/solution_0.csv`).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
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
};

/// What a report says about its run besides the planner's result.
struct PlanReportInfo {
  std::string planner = "prm";
  double time_limit_s = 0.0;
  std::uint64_t seed = 1;
  std::optional<std::filesystem::path> file;  ///< the trajectory CSV, when written
  std::optional<search::CheckReport> check;   ///< the independent re-check, when solved
};

/// The contract's plan report (status, planner, time_limit_s, first_solution_ms,
/// planning_time_ms, nodes, trapped_fraction, solutions[{cost_s, length_m, homotopy, file}])
/// plus: seed, reason, best_cost_s, first_solution_cost_s, statistics, cost_history
/// [{time_ms, cost_s}], constraint_violation and violated_limits (from the re-check).
nlohmann::json planReportJson(const search::PlanResult& result, const PlanReportInfo& info);

/// `terratraj demo`'s plan on `map`: the point vehicle from the standard start to the standard
/// goal of generated maps (terrain::standardStartGoal), at rest, with the PRM for
/// `time_limit_s`; writes the trajectory to `csv` when solved and returns the report.
nlohmann::json planDemoProblem(const terrain::ElevationMap& map, const std::filesystem::path& csv,
                               double time_limit_s, CommandContext& context);

/// Runs the command: exit 0 solved, 1 no solution (the report still printed), InputError
/// (exit 2) for bad input: an unreadable problem, a planner other than prm ("not implemented
/// yet"), a negative time limit, start or goal off the map, on lethal or no-data cells, at an
/// attitude beyond the limits, or a start turning in place.
int runPlan(const PlanOptions& options, CommandContext& context);

}  // namespace terratraj::apps
