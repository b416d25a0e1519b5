#pragma once
// Planner: the one interface of terratraj's planners (the kinodynamic PRM, A* / ARA* on the
// state lattice, TAEASL), in the sense of OMPL's ompl::base::Planner. A planner is built on one
// problem (a PlanningProblem, or a LatticeGraph over one); solve() plans until its termination
// condition stops it and returns every solution in PlanResult::solutions, best first, each
// judged by the contract's verdict (applyPlanVerdict, plan_verdict.hpp). Callers see one
// result shape whatever the planner: `solutions` (one for the PRM and A* / ARA*, up to
// homotopy_classes for TAEASL), with `trajectory` the first's.

#include "terratraj/search/plan_result.hpp"
#include "terratraj/search/termination_condition.hpp"

namespace terratraj::search {

/// A planner of one problem. Planners are not thread-safe; one solve() at a time.
class Planner {
 public:
  virtual ~Planner() = default;

  /// The contract's name of the planner ("prm", "lattice", "taeasl").
  virtual const char* name() const = 0;

  /// Plans until `termination` stops it (its iteration budget counts the planner's own
  /// iterations: PRM samples, lattice expansions). kSolved with at least one solution that
  /// passes the verdict, else kNoSolution with a reason. May be called again without clearing
  /// (OMPL's semantics): a planner continues what it built (the PRM's roadmap, A* / ARA*'s
  /// search and epsilon, the OMPL peers' trees) and never loses its best solution; TAEASL keeps
  /// nothing between calls and searches again (the same answer for the same condition). Never
  /// throws for planning failures (std::bad_alloc may escape).
  virtual PlanResult solve(TerminationCondition termination) = 0;

  /// Forgets what earlier solve() calls built: the next call plans as the first after
  /// construction did (same seed, same result for the same condition).
  virtual void clear() = 0;
};

}  // namespace terratraj::search
