#pragma once
// The one finite-difference checker of the tests (as Crocoddyl's numdiff serves every model):
// every derivative test compares its analytic derivative with centralDifferences() of the same
// function. Header-only; tests include it as "common/finite_difference.hpp".

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <sstream>

namespace terratraj::testing {

/// How the step of centralDifferences() scales with the point.
enum class StepScale {
  kAbsolute,  ///< h_j = step
  kRelative,  ///< h_j = step (1 + |x_j|)
};

/// The central-difference Jacobian of `f` at `x`: column j is (f(x + h_j e_j) - f(x - h_j e_j))
/// / (2 h_j). `f` maps an Eigen::VectorXd (the size of x) to anything convertible to an
/// Eigen::VectorXd (all of one size); a failed evaluation should record a test failure and
/// return NaN values, which then fail every comparison.
template <typename Function>
Eigen::MatrixXd centralDifferences(const Function& f, const Eigen::VectorXd& x, double step,
                                   StepScale scale = StepScale::kAbsolute) {
  Eigen::MatrixXd jacobian;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double h = scale == StepScale::kRelative ? step * (1.0 + std::abs(x(j))) : step;
    Eigen::VectorXd plus = x, minus = x;
    plus(j) += h;
    minus(j) -= h;
    const Eigen::VectorXd up = f(plus);
    const Eigen::VectorXd down = f(minus);
    if (jacobian.size() == 0) jacobian.resize(up.size(), x.size());
    // Entry by entry: GCC 12 at -O3 warns (-Warray-bounds, falsely) on Eigen's packet loads
    // of one-entry dynamic vectors.
    for (Eigen::Index i = 0; i < up.size(); ++i) jacobian(i, j) = (up(i) - down(i)) / (2.0 * h);
  }
  return jacobian;
}

/// Whether `analytic` matches `numeric` (the same shape) entrywise: |a - n| <= tolerance
/// (absolute + relative |n|). On failure the message names the worst entry and both matrices.
inline ::testing::AssertionResult matchesFiniteDifferences(const Eigen::MatrixXd& analytic,
                                                           const Eigen::MatrixXd& numeric,
                                                           double absolute, double relative = 0.0) {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    return ::testing::AssertionFailure()
           << "shapes differ: " << analytic.rows() << "x" << analytic.cols() << " vs "
           << numeric.rows() << "x" << numeric.cols();
  }
  Eigen::Index worst_row = 0, worst_col = 0;
  double worst_excess = -1.0;
  for (Eigen::Index i = 0; i < analytic.rows(); ++i) {
    for (Eigen::Index j = 0; j < analytic.cols(); ++j) {
      const double allowed = absolute + relative * std::abs(numeric(i, j));
      const double excess = std::abs(analytic(i, j) - numeric(i, j)) - allowed;
      if (!(excess <= 0.0) && (std::isnan(excess) || excess > worst_excess)) {
        worst_excess = std::isnan(excess) ? INFINITY : excess;
        worst_row = i;
        worst_col = j;
      }
    }
  }
  if (worst_excess < 0.0) return ::testing::AssertionSuccess();
  std::ostringstream text;
  text << "entry (" << worst_row << ", " << worst_col << "): analytic "
       << analytic(worst_row, worst_col) << ", finite differences " << numeric(worst_row, worst_col)
       << " (tolerance " << absolute << " + " << relative << " relative)\nanalytic\n"
       << analytic << "\nfinite differences\n"
       << numeric;
  return ::testing::AssertionFailure() << text.str();
}

}  // namespace terratraj::testing
