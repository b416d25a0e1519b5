#include "terratraj/ocp/iteration_stall.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {

IterationStall::IterationStall(const StallAcceptance& acceptance)
    : acceptance_(acceptance), costs_(static_cast<std::size_t>(std::max(acceptance.window, 0))) {}

bool IterationStall::accept(double cost, double constraint_violation, double dual_infeasibility,
                            double barrier) {
  if (costs_.empty()) return false;
  costs_[static_cast<std::size_t>(recorded_) % costs_.size()] = cost;
  ++recorded_;
  if (recorded_ < static_cast<int>(costs_.size()) || costs_.size() < 2) return false;
  if (!(constraint_violation <= acceptance_.constraint_violation) ||
      !(dual_infeasibility <= acceptance_.dual_infeasibility) ||
      !(barrier <= acceptance_.barrier)) {
    return false;
  }
  const auto [lo, hi] = std::minmax_element(costs_.begin(), costs_.end());
  return std::isfinite(*lo) && std::isfinite(*hi) &&
         *hi - *lo <= acceptance_.cost_change * std::max(1.0, std::abs(cost));
}

}  // namespace terratraj::ocp
