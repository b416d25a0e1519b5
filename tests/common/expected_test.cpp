// terratraj::Expected: a value or the reason there is none.

#include "terratraj/terrain/expected.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace terratraj {
namespace {

Expected<std::vector<int>> firstN(int n) {
  if (n < 0) return unexpected("n = " + std::to_string(n) + " is negative");
  std::vector<int> out;
  for (int i = 0; i < n; ++i) out.push_back(i);
  return out;
}

TEST(Expected, HoldsAValueOrAReason) {
  const Expected<std::vector<int>> three = firstN(3);
  ASSERT_TRUE(three.ok());
  EXPECT_TRUE(static_cast<bool>(three));
  EXPECT_EQ(three->size(), 3u);
  EXPECT_EQ((*three)[2], 2);
  EXPECT_TRUE(three.reason().empty());

  const Expected<std::vector<int>> bad = firstN(-1);
  EXPECT_FALSE(bad.ok());
  EXPECT_FALSE(static_cast<bool>(bad));
  EXPECT_EQ(bad.reason(), "n = -1 is negative");
  EXPECT_THROW(bad.value(), std::bad_optional_access);
}

TEST(Expected, ItsValueCanBeMovedOut) {
  Expected<std::vector<int>> two = firstN(2);
  std::vector<int> moved = std::move(*two);
  EXPECT_EQ(moved, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace terratraj
