#include "terratraj/search/plan_result.hpp"

namespace terratraj::search {

const char* planStatusName(PlanStatus status) {
  switch (status) {
    case PlanStatus::kSolved:
      return "solved";
    case PlanStatus::kNoSolution:
      return "no_solution";
  }
  return "unknown";
}

}  // namespace terratraj::search
