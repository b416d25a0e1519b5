#include "terratraj/search/termination_condition.hpp"

#include <cmath>

namespace terratraj::search {

TerminationCondition TerminationCondition::timeLimit(double seconds) {
  TerminationCondition condition;
  condition.time_limit_s_ = std::isnan(seconds) || seconds < 0.0 ? 0.0 : seconds;
  return condition;
}

TerminationCondition TerminationCondition::iterationLimit(std::size_t iterations) {
  TerminationCondition condition;
  condition.max_iterations_ = iterations;
  return condition;
}

}  // namespace terratraj::search
