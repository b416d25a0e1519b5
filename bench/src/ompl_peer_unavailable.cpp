// The OMPL peers in a build without OMPL (-DTERRATRAJ_WITH_OMPL=OFF): unavailable.

#include "terratraj/bench/ompl_peer.hpp"

namespace terratraj::bench {

bool omplPeersAvailable() { return false; }

OmplRun runOmplPeer(const search::PlanningProblem& /*problem*/, OmplPlanner /*planner*/,
                    double /*budget_s*/, std::uint64_t /*seed*/) {
  OmplRun run;
  run.status = "unavailable: built with -DTERRATRAJ_WITH_OMPL=OFF";
  return run;
}

}  // namespace terratraj::bench
