#pragma once
// The search seed of solveSeeded(): when no Dubins word gave a verified trajectory (obstacles in
// the way of every word, or terrain they cross badly), the kinodynamic PRM's first solution,
// refined in its homotopy class (refine::CandidateRefiner).

#include <optional>
#include <string>

#include "terratraj/refine/seeded_solver.hpp"

namespace terratraj::refine {

/// The search seed's PRM budget [s]: options.search_time_s (absent: kDefaultSearchTimeS), and,
/// with `time_left_s`, at most half of it (the refinement of the PRM's path needs the rest).
double searchSeedBudget(const SeededSolveOptions& options, std::optional<double> time_left_s);

/// Plans with the PRM for searchSeedBudget() at most (stopping at its first solution; the
/// seed options.search_seed), then refines that candidate with the method of `options` (auto:
/// collocation) within `time_left_s`. The result's status is the refinement's (the verdict
/// against the exact goal); kInfeasible with the reason when the PRM finds nothing (`why`: why
/// a search was needed, the start of that reason).
SeededSolution solveFromSearch(const models::TerrainFollowingModel& vehicle,
                               const ocp::BoundaryValueProblem& problem,
                               const terrain::ElevationMap& map, const SeededSolveOptions& options,
                               std::optional<double> time_left_s, const std::string& why);

}  // namespace terratraj::refine
