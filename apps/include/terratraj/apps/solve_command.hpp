#pragma once
// `terratraj solve`: one boundary-value problem, start to goal, optimal for the cost
// (004_...), with the contract's JSON report and trajectory CSV.

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::apps {

/// Options of `terratraj solve`.
struct SolveOptions {
  std::filesystem::path problem;
  std::optional<std::string> method;         ///< overrides solver.method
  std::optional<std::filesystem::path> out;  ///< trajectory CSV
};

/// The parametric problem a problem file describes (tables not attached). Throws InputError
/// for a method the parametric solvers do not provide.
ocp::BoundaryValueProblem boundaryValueProblem(const ProblemSpec& problem);
/// The solver settings a problem file describes.
ocp::BoundaryValueOptions boundaryValueOptions(const ProblemSpec& problem);

/// The contract's solve report for a solution.
nlohmann::json solveReportJson(const ocp::BoundaryValueSolution& solution,
                               const ocp::BoundaryValueOptions& options);

/// `terratraj demo`'s boundary-value problem on `map`: the rocker-bogie rover at 0.5 m/s from
/// 15 % of the map's width to 6 m further (1.5 m left, heading +0.3 rad), minimum time + slope
/// dwell (alpha = 1), solved by newton; writes the trajectory to `csv` and returns the report.
nlohmann::json solveDemoProblem(const terrain::ElevationMap& map, const std::filesystem::path& csv,
                                CommandContext& context);

/// Runs the command: exit 0 when converged, 1 when the problem was read but not solved (the
/// report still printed), InputError (exit 2) for bad input.
int runSolve(const SolveOptions& options, CommandContext& context);

}  // namespace terratraj::apps
