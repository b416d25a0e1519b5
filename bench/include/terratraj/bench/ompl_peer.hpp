#pragma once
// OMPL peers of the planners suite (`terratraj bench planners`): OMPL 1.5's control-based RRT
// (with our steering function) and SST (time as the cost) on a search::PlanningProblem, with
// the same propagator (search::ExtensionIntegrator: an OMPL control is an extension request,
// a target and a target speed) and the same validity checks (the integrator's: map, lethal
// cells, pitch, roll, speed caps and tables). OMPL is a benchmark peer only.

#include <cstdint>
#include <memory>
#include <string>

#include "terratraj/search/planner.hpp"
#include "terratraj/search/planning_problem.hpp"

namespace terratraj::bench {

enum class OmplPlanner { kRrt, kSst };
/// "ompl_rrt", "ompl_sst".
inline const char* omplPlannerName(OmplPlanner planner) {
  return planner == OmplPlanner::kRrt ? "ompl_rrt" : "ompl_sst";
}

/// Whether this build has the peers (false with -DTERRATRAJ_WITH_OMPL=OFF: an
/// OmplPeerPlanner then plans nothing and says so).
bool omplPeersAvailable();

/// An OMPL peer behind the planners' interface (search::Planner): solve() returns the same
/// PlanResult as terratraj's planners, its one solution (OMPL's exact solution, re-integrated
/// with the extension integrator, every column filled; its duration is the cost) judged by the
/// same verdict (search::applyPlanVerdict). The termination condition's time limit, stop flag
/// and stop-at-first-solution apply; its iteration budget does not (OMPL counts none). RRT
/// returns at its first solution. solve() again continues OMPL's tree (clear() starts over);
/// times count planning time summed over the calls [ms]. Not thread-safe.
class OmplPeerPlanner final : public search::Planner {
 public:
  /// `problem` must outlive the planner. OMPL's random seed is process-wide: it is set from
  /// `seed` by the first peer built in the process only (later peers continue its sequence).
  OmplPeerPlanner(const search::PlanningProblem& problem, OmplPlanner planner, std::uint64_t seed);
  ~OmplPeerPlanner() override;
  OmplPeerPlanner(const OmplPeerPlanner&) = delete;
  OmplPeerPlanner& operator=(const OmplPeerPlanner&) = delete;

  /// "ompl_rrt" or "ompl_sst".
  const char* name() const override;
  /// Plans; kNoSolution's reason names OMPL's status ("unavailable: ..." without OMPL).
  search::PlanResult solve(search::TerminationCondition termination) override;
  /// A new tree and no solution.
  void clear() override;
  /// OMPL's PlannerStatus of the last solve() as text ("not run" before it).
  const std::string& omplStatus() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace terratraj::bench
