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

/// Which of the PRM's routes solveFromSearch() refines first.
enum class RouteOrder {
  /// Its first solution, then (after a failed refinement) better routes: when no result exists
  /// yet. Better routes can pass closer to what the refiner must keep off (on the gully DEM,
  /// routes 8,000 milestones on pass the band beside no data where the refiner's guess cannot
  /// be placed; the first solution's refinement converges).
  kFirstSolutionFirst,
  /// Its best route search_improve_milestones after the first solution: when the search seed
  /// can only improve on a converged result (a shorter route, likelier to beat it, and faster
  /// to refine: a davosdorf Segway problem's first route takes 7-20 s to fail, the route 8,000
  /// milestones on converges in 1.7 s), and when a retry follows a first route's refinement
  /// the clock cut.
  kImprovedFirst,
};

/// Plans with the PRM for searchSeedBudget() at most (stopping at its first solution; the
/// seed options.search_seed), then refines that candidate (kImprovedFirst: the PRM's best route
/// options.search_improve_milestones later) with the method of `options` (auto: collocation)
/// within `time_left_s`. When that refinement fails on its own (not by the clock), the PRM
/// continues for options.search_improve_milestones more milestones and its
/// better route is refined, up to options.search_improvements times (the seed's name says
/// which route the result came from; a failure's reason names the earlier routes' verdicts).
/// The result's status is the last refinement's (the verdict against the exact goal);
/// time_limit_reached only when the clock cut the first refinement (a retry starts the chain
/// again); kInfeasible with the reason when the PRM finds nothing (`why`: why a search was
/// needed, the start of that reason).
SeededSolution solveFromSearch(const models::TerrainFollowingModel& vehicle,
                               const ocp::BoundaryValueProblem& problem,
                               const terrain::ElevationMap& map, const SeededSolveOptions& options,
                               std::optional<double> time_left_s, const std::string& why,
                               RouteOrder order = RouteOrder::kFirstSolutionFirst);

}  // namespace terratraj::refine
