#pragma once
// The pieces of the commands' JSON reports that more than one command writes: an optimiser's
// iteration history, a re-simulated trajectory's figures (solve, refine, bench), a trajectory's
// figures and a refinement's block (refine, plan --refine). Each command's own report is beside
// its command (solveReportJson, refineReportJson, planReportJson).

#include <filesystem>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/refine/candidate_refiner.hpp"

namespace terratraj::apps {

/// The report's `history`: per iteration, iteration, terminal_error, cost,
/// lagrangian_gradient, step (and heading_error when asked); non-finite values as null.
nlohmann::json iterationHistoryJson(const std::vector<ocp::IterationRecord>& history,
                                    bool heading_error);

/// The report's figures that come from an independent re-simulation: final_time_s, cost,
/// length_m, terminal_error, max_abs_pitch_rad, max_abs_roll_rad, max_speed,
/// constraint_violation, violated_limit, slope_dwell_rad2_s, verified (null where it failed).
nlohmann::json verifiedTrajectoryJson(const ocp::VerifiedTrajectory& verified);

/// The figures of a trajectory as JSON (cost, duration_s, length_m, max_abs_pitch_rad,
/// max_abs_roll_rad, max_speed, min_clearance_m, check {ok, constraint_violation,
/// violated_limits}, homotopy).
nlohmann::json trajectoryFiguresJson(const refine::TrajectoryFigures& figures);

/// The `refined` block of a plan report's solution: status, reason, cost_s (duration), cost
/// (the problem's cost), file, method, method_rule, iterations, solve_time_ms and the refined
/// trajectory's figures, homotopy (after), homotopy_kept, cost_ratio.
nlohmann::json refinedSolutionJson(const refine::RefinementResult& result,
                                   const std::optional<std::filesystem::path>& file);

}  // namespace terratraj::apps
