#pragma once
// IterationStall: accepts an interior-point solve that has stopped making progress at a
// feasible, nearly stationary point.
//
// On terrain the NLP's second derivatives jump where the bicubic surface (C1) crosses a cell
// edge; Newton steps near such a kink can cycle for hundreds of iterations between points whose
// cost agrees to 1e-6, with the constraints met on one and missed by 1e-4 on the next, and the
// dual infeasibility stuck near 1e-3 (measured on davosdorf, docs/benchmarks.md). Ipopt's own
// acceptable test needs its error under acceptable_tol for consecutive iterations, which the
// alternation breaks. This test looks at the last `window` iterations instead.

#include <vector>

namespace terratraj::ocp {

/// When a stalled solve is accepted. All four must hold at the current iterate.
struct StallAcceptance {
  int window = 20;  ///< iterations the cost must have stayed within `cost_change`, >= 2; 0: off
  double cost_change = 1e-5;           ///< (max - min) / max(1, |cost|) over the window, relative
  double constraint_violation = 1e-6;  ///< the iterate's max constraint violation (unscaled)
  double dual_infeasibility = 1e-2;    ///< the iterate's (scaled) dual infeasibility
  double barrier = 1e-6;               ///< the barrier parameter mu, at most
};

/// Fed once per iteration; allocates only in its constructor.
class IterationStall {
 public:
  explicit IterationStall(const StallAcceptance& acceptance);

  /// Records one iteration (its cost, max constraint violation, dual infeasibility and barrier
  /// parameter) and says whether the solve may stop here, at this iterate, as converged.
  bool accept(double cost, double constraint_violation, double dual_infeasibility, double barrier);

  /// Iterations recorded.
  int iterations() const { return recorded_; }

 private:
  StallAcceptance acceptance_;
  std::vector<double> costs_;  ///< ring buffer of the last `window` costs
  int recorded_ = 0;
};

}  // namespace terratraj::ocp
