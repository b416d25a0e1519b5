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
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::apps {

/// Options of `terratraj solve`.
struct SolveOptions {
  std::filesystem::path problem;
  std::optional<std::string> method;         ///< overrides solver.method
  std::optional<std::filesystem::path> out;  ///< trajectory CSV
  /// Shooting / collocation: start from this trajectory or x,y path (CSV) instead of the
  /// parametric solution.
  std::optional<std::filesystem::path> guess;
};

/// The parametric problem a problem file describes (tables not attached). Throws InputError
/// for a method the parametric solvers do not provide.
ocp::BoundaryValueProblem boundaryValueProblem(const ProblemSpec& problem);
/// The solver settings a problem file describes.
ocp::BoundaryValueOptions boundaryValueOptions(const ProblemSpec& problem);

/// Whether a method is direct transcription (shooting, collocation).
bool isTranscriptionMethod(SolverMethod method);
/// The direct-transcription settings a problem file describes (the clearance map, when
/// solver.min_clearance_m is set, is attached by the caller).
ocp::DirectTranscriptionOptions transcriptionOptions(const ProblemSpec& problem);
/// The contract's report of a direct-transcription solve: `verified` is its independent
/// re-simulation; `guess_source` says where the initial guess came from.
nlohmann::json transcriptionReportJson(const ocp::TranscriptionSolution& solution,
                                       const ocp::VerifiedTrajectory& verified,
                                       const ocp::DirectTranscriptionOptions& options,
                                       const std::string& guess_source);

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
