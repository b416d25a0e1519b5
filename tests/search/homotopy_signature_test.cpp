#include "terratraj/search/homotopy_signature.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <unordered_map>

namespace terratraj::search {
namespace {

HomotopySignature word(std::initializer_list<FrameCrossing> crossings) {
  HomotopySignature signature;
  for (const FrameCrossing& c : crossings) signature.append(c);
  return signature;
}

TEST(HomotopySignature, StartsEmptyAndPrintsAsEmptyString) {
  const HomotopySignature signature;
  EXPECT_TRUE(signature.empty());
  EXPECT_EQ(signature.size(), 0u);
  EXPECT_EQ(signature.toString(), "");
}

TEST(HomotopySignature, CrossingStraightBackCancels) {
  EXPECT_TRUE(word({{0, +1}, {0, -1}}).empty());
  EXPECT_TRUE(word({{3, -1}, {3, +1}}).empty());
  const HomotopySignature a = word({{0, +1}, {1, +1}, {1, -1}});
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a.crossings()[0], (FrameCrossing{0, +1}));
  EXPECT_EQ(a.toString(), "a+");
  // Nested cancellation: a+ b+ b- a- is empty.
  EXPECT_TRUE(word({{0, +1}, {1, +1}, {1, -1}, {0, -1}}).empty());
}

TEST(HomotopySignature, SameDirectionOrNonAdjacentDoesNotCancel) {
  EXPECT_EQ(word({{0, +1}, {0, +1}}).toString(), "a+a+");
  EXPECT_EQ(word({{0, +1}, {1, +1}, {0, -1}}).toString(), "a+b+a-");
}

TEST(HomotopySignature, DirectionIsNormalisedToPlusOrMinusOne) {
  const HomotopySignature signature = word({{2, -7}, {4, 0}});
  ASSERT_EQ(signature.size(), 2u);
  EXPECT_EQ(signature.crossings()[0].direction, -1);
  EXPECT_EQ(signature.crossings()[1].direction, +1);
  EXPECT_EQ(signature.toString(), "c-e+");
}

TEST(HomotopySignature, FrameNamesAreSpreadsheetColumns) {
  EXPECT_EQ(HomotopySignature::frameName(0), "a");
  EXPECT_EQ(HomotopySignature::frameName(1), "b");
  EXPECT_EQ(HomotopySignature::frameName(25), "z");
  EXPECT_EQ(HomotopySignature::frameName(26), "aa");
  EXPECT_EQ(HomotopySignature::frameName(27), "ab");
  EXPECT_EQ(HomotopySignature::frameName(51), "az");
  EXPECT_EQ(HomotopySignature::frameName(52), "ba");
  EXPECT_EQ(HomotopySignature::frameName(701), "zz");
  EXPECT_EQ(HomotopySignature::frameName(702), "aaa");
  EXPECT_EQ(HomotopySignature::frameName(-1), "?");
}

TEST(HomotopySignature, ToStringJoinsNamesAndSigns) {
  EXPECT_EQ(word({{0, +1}, {1, -1}}).toString(), "a+b-");
  EXPECT_EQ(word({{26, -1}, {2, +1}}).toString(), "aa-c+");
}

TEST(HomotopySignature, AppendingASignatureConcatenatesWithCancellation) {
  HomotopySignature left = word({{0, +1}, {1, +1}});
  left.append(word({{1, -1}, {2, -1}}));
  EXPECT_EQ(left.toString(), "a+c-");
  HomotopySignature twice = word({{0, +1}});
  twice.append(twice);
  EXPECT_EQ(twice.toString(), "a+a+");
  twice.clear();
  EXPECT_TRUE(twice.empty());
}

TEST(HomotopySignature, EqualityHashAndOrder) {
  const HomotopySignature a = word({{0, +1}, {1, -1}});
  const HomotopySignature b = word({{0, +1}, {2, +1}, {2, -1}, {1, -1}});
  const HomotopySignature c = word({{0, +1}, {1, +1}});
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.hash(), b.hash());
  EXPECT_NE(a, c);
  EXPECT_NE(a.hash(), c.hash());
  EXPECT_NE(HomotopySignature().hash(), word({{0, +1}}).hash());
  // Stable: the empty word hashes to the FNV-1a offset basis.
  EXPECT_EQ(HomotopySignature().hash(), static_cast<std::size_t>(14695981039346656037ull));

  EXPECT_TRUE(HomotopySignature() < a);
  EXPECT_TRUE(a < c);  // same length, b- < b+
  EXPECT_FALSE(c < a);
  EXPECT_FALSE(a < b);
  const std::set<HomotopySignature> ordered{c, a, HomotopySignature(), b};
  EXPECT_EQ(ordered.size(), 3u);
  EXPECT_EQ(ordered.begin()->toString(), "");
}

TEST(HomotopySignature, WorksAsAnUnorderedMapKey) {
  std::unordered_map<HomotopySignature, int, HomotopySignatureHash> classes;
  classes[HomotopySignature()] = 1;
  classes[word({{0, +1}})] = 2;
  classes[word({{0, +1}, {1, +1}, {1, -1}})] += 10;
  EXPECT_EQ(classes.size(), 2u);
  EXPECT_EQ(classes[word({{0, +1}})], 12);
}

}  // namespace
}  // namespace terratraj::search
