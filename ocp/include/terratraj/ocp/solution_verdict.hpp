#pragma once
// The verdict of a boundary-value solve (parametric or direct transcription): the
// requirements its trajectory is held to, and how models::judgeTrajectory()'s outcome becomes
// the contract's status. solveBoundaryValue() and solveTranscription() use these; nothing else
// in ocp decides `converged`.

#include <string>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::ocp {

/// What a solve's trajectory must meet: the map rules of `map` (none when null), the
/// problem's limits and tables, its start (exactly: 1e-6 m, 1e-6 m/s) and its goal within
/// `criteria` (position, heading) and within 1e-3 v_max + 1e-6 m/s of the goal speed; limits
/// within 1e-3 relative, 1e-6 absolute. The pointers are kept: `vehicle`, `map` and the
/// problem's tables must outlive the result.
models::TrajectoryRequirements solveRequirements(const models::TerrainFollowingModel& vehicle,
                                                 const BoundaryValueProblem& problem,
                                                 const ConvergenceCriteria& criteria,
                                                 const terrain::ElevationMap* map);

/// The final status of a solve whose solver ended with `solver_status` and whose written
/// trajectory got `verdict`: the solver's status when it did not converge; else kConverged
/// when the verdict passes, kInfeasible when it crosses the map or breaks a limit, kDiverged
/// when it misses the goal or cannot be used.
SolveStatus statusAfterVerdict(SolveStatus solver_status, const models::TrajectoryVerdict& verdict);

/// The largest violation of a limit, table or map rule in `check` (goal and start rules
/// excluded), in the limit's units, and its name ("" when none).
std::pair<double, std::string> largestLimitViolation(const models::CheckReport& check);

}  // namespace terratraj::ocp
