#pragma once
// `terratraj solve`: one boundary-value problem, start to goal, optimal for the cost
// (004_...), with the contract's JSON report and trajectory CSV.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/refine/seeded_solver.hpp"
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
  std::optional<std::filesystem::path> plot;  ///< map PNG (and -profiles, -convergence)
};

/// The contract's report of a direct-transcription solve: `verified` is its independent
/// re-simulation; `guess_source` says where the initial guess came from.
nlohmann::json transcriptionReportJson(const ocp::TranscriptionSolution& solution,
                                       const ocp::VerifiedTrajectory& verified,
                                       const ocp::DirectTranscriptionOptions& options,
                                       const std::string& guess_source);

/// The contract's solve report for a solution.
nlohmann::json solveReportJson(const ocp::BoundaryValueSolution& solution,
                               const ocp::BoundaryValueOptions& options);

/// Runs the command: exit 0 when converged, 1 when the problem was read but not solved (the
/// report still printed), InputError (exit 2) for bad input.
int runSolve(const SolveOptions& options, CommandContext& context);

}  // namespace terratraj::apps
