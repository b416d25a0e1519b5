#pragma once
// IterationDivergence: when an interior-point solve has blown up and should stop. From a
// hopeless start (a word across a pocket of davosdorf, docs/benchmarks.md) Ipopt's dual
// infeasibility climbs past 1e10 and keeps climbing (1e14 after 146 iterations) while the
// constraint violation stays put; its KKT matrices degenerate and MUMPS's factorisations slow
// from milliseconds to seconds, so one iteration can run seconds past a time limit. Diverging
// multipliers with a constraint violation that stays put are the mark of a point of local
// infeasibility, which Ipopt's restoration phase would prove only much later: the solve stops
// as locally infeasible. A Segway problem that converges after 1,200 iterations stays below
// 5e3.
//
// The climb can also be steep: a slope-dwell word on davosdorf went from 6e10 to 3e13 and 6e15
// in two iterations, and the next factorisation took 26 s (MUMPS asked for more memory four
// times), 17 s past a 10 s budget. Above `blow_up` the solve stops at once.

namespace terratraj::ocp {

/// When a solve counts as diverged.
struct DivergenceStop {
  /// Consecutive iterations above `dual_infeasibility`, >= 1; 0: never stops.
  int window = 20;
  double dual_infeasibility = 1e10;  ///< Ipopt's (scaled) dual infeasibility, > 0
  /// One iteration above this (scaled) dual infeasibility stops the solve at once (when
  /// `window` > 0), >= `dual_infeasibility`.
  double blow_up = 1e12;
};

/// Fed once per iteration; allocates nothing.
class IterationDivergence {
 public:
  explicit IterationDivergence(const DivergenceStop& stop) : stop_(stop) {}

  /// Records one iteration's dual infeasibility (NaN counts as above) and says whether the
  /// solve has diverged: `window` iterations in a row above the threshold, or one above
  /// `blow_up` (a NaN counts in the window only).
  bool diverged(double dual_infeasibility) {
    if (stop_.window <= 0) return false;
    run_ = dual_infeasibility <= stop_.dual_infeasibility ? 0 : run_ + 1;
    return run_ >= stop_.window || dual_infeasibility > stop_.blow_up;
  }

 private:
  DivergenceStop stop_;
  int run_ = 0;  ///< iterations in a row above the threshold
};

}  // namespace terratraj::ocp
