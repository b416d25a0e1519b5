// The finite-difference checker every derivative test uses: it must pass a right derivative and
// catch a wrong one (else every derivative test built on it could not fail).

#include "common/finite_difference.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace terratraj::testing {
namespace {

Eigen::VectorXd f(const Eigen::VectorXd& x) {
  return Eigen::Vector2d(std::sin(x(0)) * x(1), x(1) * x(1) + 3.0 * x(0));
}

Eigen::Matrix2d jacobianOfF(const Eigen::Vector2d& x) {
  Eigen::Matrix2d j;
  j << std::cos(x(0)) * x(1), std::sin(x(0)), 3.0, 2.0 * x(1);
  return j;
}

TEST(FiniteDifferenceChecker, PassesTheRightDerivativeAndCatchesAWrongOne) {
  const Eigen::Vector2d x(0.7, -40.0);
  for (const StepScale scale : {StepScale::kAbsolute, StepScale::kRelative}) {
    const Eigen::MatrixXd numeric = centralDifferences(f, x, 1e-6, scale);
    ASSERT_EQ(numeric.rows(), 2);
    ASSERT_EQ(numeric.cols(), 2);
    EXPECT_TRUE(matchesFiniteDifferences(jacobianOfF(x), numeric, 1e-6, 1e-8));
    Eigen::Matrix2d wrong = jacobianOfF(x);
    wrong(1, 0) += 1e-4;
    const ::testing::AssertionResult caught = matchesFiniteDifferences(wrong, numeric, 1e-6, 1e-8);
    EXPECT_FALSE(caught);
    EXPECT_NE(std::string(caught.message()).find("entry (1, 0)"), std::string::npos)
        << caught.message();
  }
  // A failed evaluation (NaN) fails the comparison; so does a shape mismatch.
  const auto broken = [](const Eigen::VectorXd&) { return Eigen::Vector2d(NAN, 0.0); };
  EXPECT_FALSE(matchesFiniteDifferences(jacobianOfF(x), centralDifferences(broken, x, 1e-6), 1.0));
  EXPECT_FALSE(matchesFiniteDifferences(Eigen::Matrix3d::Zero(), Eigen::Matrix2d::Zero(), 1.0));
}

}  // namespace
}  // namespace terratraj::testing
