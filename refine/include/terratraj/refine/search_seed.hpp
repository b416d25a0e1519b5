#pragma once
// The search seed of solveSeeded(): when no Dubins word gave a verified trajectory (obstacles in
// the way of every word, or terrain they cross badly), the kinodynamic PRM's first solution,
// refined in its homotopy class (refine::CandidateRefiner); a better route of the PRM when that
// refinement fails.

#include <optional>
#include <string>

#include "terratraj/refine/seeded_solver.hpp"

namespace terratraj::refine {

/// The search seed's PRM budget [s]: options.search_time_s (absent: kDefaultSearchTimeS), and,
/// with `time_left_s`, at most half of it (the refinement of the PRM's path needs the rest).
double searchSeedBudget(const SeededSolveOptions& options, std::optional<double> time_left_s);

/// Plans with the PRM for searchSeedBudget() at most (stopping at its first solution; the
/// seed options.search_seed), then refines that candidate with the method of `options` (auto:
/// collocation) within `time_left_s`. When that refinement fails on its own (not by the
/// clock), the PRM continues for options.search_improve_milestones more milestones and its
/// better route is refined, up to options.search_improvements times (the seed's name says
/// which route the result came from; a failure's reason names the earlier routes' verdicts).
/// The result's status is the last refinement's (the verdict against the exact goal);
/// time_limit_reached only when the clock cut the first refinement (a retry starts the chain
/// again); kInfeasible with the reason when the PRM finds nothing (`why`: why a search was
/// needed, the start of that reason).
SeededSolution solveFromSearch(const models::TerrainFollowingModel& vehicle,
                               const ocp::BoundaryValueProblem& problem,
                               const terrain::ElevationMap& map, const SeededSolveOptions& options,
                               std::optional<double> time_left_s, const std::string& why);

}  // namespace terratraj::refine
