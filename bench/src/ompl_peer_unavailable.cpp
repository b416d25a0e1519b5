// The OMPL peers in a build without OMPL (-DTERRATRAJ_WITH_OMPL=OFF): unavailable.

#include "terratraj/bench/ompl_peer.hpp"

namespace terratraj::bench {

namespace {
const char* const kUnavailable = "unavailable: built with -DTERRATRAJ_WITH_OMPL=OFF";
}  // namespace

bool omplPeersAvailable() { return false; }

struct OmplPeerPlanner::Impl {
  OmplPlanner kind;
  std::string status = kUnavailable;
};

OmplPeerPlanner::OmplPeerPlanner(const search::PlanningProblem& /*problem*/, OmplPlanner planner,
                                 std::uint64_t /*seed*/)
    : impl_(std::make_unique<Impl>(Impl{planner})) {}

OmplPeerPlanner::~OmplPeerPlanner() = default;

const char* OmplPeerPlanner::name() const { return omplPlannerName(impl_->kind); }

search::PlanResult OmplPeerPlanner::solve(search::TerminationCondition /*termination*/) {
  search::PlanResult result;
  result.reason = kUnavailable;
  return result;
}

void OmplPeerPlanner::clear() {}

const std::string& OmplPeerPlanner::omplStatus() const { return impl_->status; }

}  // namespace terratraj::bench
