#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "lattice_fixtures.hpp"
#include "terratraj/search/primitive_file.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::search {
namespace {

using testing::defaultPrimitives;

// Every heading has primitives; each starts at its node and heading, ends exactly on its
// lattice offset and heading, has zero curvature at both ends, and respects kappa_max and (at
// the generation speed) sigma_max.
TEST(MotionPrimitives, DefaultSetServesEveryHeadingWithinTheLimits) {
  const PrimitiveSet& set = defaultPrimitives();
  const models::VehicleLimits limits;
  ASSERT_EQ(set.checkAgainst(LatticeSpec{}, &limits), std::nullopt);
  EXPECT_EQ(set.by_heading.size(), 16u);
  EXPECT_GE(set.size(), 16u * 5u);
  for (const auto& list : set.by_heading) {
    ASSERT_GE(list.size(), 5u);
    int turning = 0;
    for (const MotionPrimitive& p : list) {
      EXPECT_LE(p.max_abs_curvature, limits.kappa_max * (1 + 1e-6));
      // Stored samples are every 5 cm: the rate between them is within 2 % of sigma / speed.
      EXPECT_LE(p.max_abs_curvature_rate * set.generation.speed, 1.02 * limits.sigma_max);
      EXPECT_NEAR(p.samples.back().x, p.offset.x() * 0.5, 1e-9);
      EXPECT_NEAR(p.samples.back().y, p.offset.y() * 0.5, 1e-9);
      EXPECT_NEAR(p.length, p.samples.back().s, 1e-12);
      turning += p.end_heading != p.start_heading ? 1 : 0;
    }
    EXPECT_GE(turning, 4);  // turns by -2, -1, +1, +2 heading indices
  }
}

// Rotating a heading's primitives by 90 degrees gives those of heading + 4 (16 headings).
TEST(MotionPrimitives, QuarterTurnSymmetry) {
  const PrimitiveSet& set = defaultPrimitives();
  for (std::size_t n = 0; n < set.by_heading[1].size(); ++n) {
    const MotionPrimitive& a = set.by_heading[1][n];
    const MotionPrimitive& b = set.by_heading[5][n];
    EXPECT_EQ(b.offset, Eigen::Vector2i(-a.offset.y(), a.offset.x()));
    EXPECT_EQ(b.end_heading, (a.end_heading + 4) % 16);
  }
}

// A vehicle whose curvature may change fast (sigma_max 20 1/(m s), kappa_max 1 1/m): kappa_max
// binds, not sigma_max. Every heading and turn gets a primitive that holds kappa_max. (Before:
// offsets chosen by sigma_max alone asked for S-bends kappa_max cannot make, and the solver's
// curvature passed kappa_max by 4.5e-4 between its constraint points: no lattice, exit 2.)
TEST(MotionPrimitives, AFastSteeringVehicleGetsAFullSetWithinKappaMax) {
  models::VehicleLimits limits;
  limits.kappa_max = 1.0;
  limits.sigma_max = 20.0;
  const PrimitiveGenerationResult result = generatePrimitives(LatticeSpec{}, limits);
  for (const std::string& f : result.failures) ADD_FAILURE() << f;
  EXPECT_EQ(result.set.checkAgainst(LatticeSpec{}, &limits), std::nullopt);
  for (const auto& list : result.set.by_heading) {
    EXPECT_GE(list.size(), 5u);
    for (const MotionPrimitive& p : list) {
      EXPECT_LE(p.max_abs_curvature, limits.kappa_max * (1 + 1e-6));
    }
  }
}

TEST(MotionPrimitives, AnyHeadingCountIsAllowed) {
  LatticeSpec lattice;
  lattice.heading_count = 6;  // not a multiple of 4: every heading solved
  PrimitiveGenerationOptions options;
  options.turns = {-1, 1};
  options.straight_lengths = {1.5};
  const PrimitiveGenerationResult result =
      generatePrimitives(lattice, models::VehicleLimits{}, options);
  EXPECT_EQ(result.set.checkAgainst(lattice, nullptr), std::nullopt) << result.failures.size();
  EXPECT_EQ(result.set.by_heading.size(), 6u);
}

TEST(MotionPrimitives, FileRoundTripAndConsistencyChecks) {
  const PrimitiveSet& set = defaultPrimitives();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "tt_primitives_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "set.json";
  writePrimitiveFile(set, file);
  const PrimitiveSet read = readPrimitiveFile(file);
  ASSERT_EQ(read.size(), set.size());
  EXPECT_EQ(read.checkAgainst(LatticeSpec{}, nullptr), std::nullopt);
  EXPECT_EQ(read.by_heading[3][2].offset, set.by_heading[3][2].offset);
  EXPECT_DOUBLE_EQ(read.by_heading[3][2].samples[7].y, set.by_heading[3][2].samples[7].y);

  LatticeSpec other;
  other.heading_count = 8;
  const std::optional<std::string> headings = read.checkAgainst(other, nullptr);
  ASSERT_TRUE(headings);
  EXPECT_NE(headings->find("heading_count"), std::string::npos);
  other = LatticeSpec{};
  other.resolution = 0.25;
  ASSERT_TRUE(read.checkAgainst(other, nullptr));
  EXPECT_NE(read.checkAgainst(other, nullptr)->find("resolution_m"), std::string::npos);
  models::VehicleLimits tight;
  tight.kappa_max = 0.1;
  ASSERT_TRUE(read.checkAgainst(LatticeSpec{}, &tight));
  EXPECT_NE(read.checkAgainst(LatticeSpec{}, &tight)->find("kappa_max"), std::string::npos);

  // Malformed files name the file and key.
  const std::filesystem::path bad = dir / "bad.json";
  std::ofstream(bad) << R"({"format": "terratraj-primitives", "version": 1,
    "lattice": {"resolution_m": 0.5, "heading_count": 16}, "sample_spacing_m": 0.05,
    "primitives": [{"start_heading": 0, "end_heading": 0, "offset": [2, 0],
                    "t": [0, 1], "s": [0, 1], "x": [0, 1], "y": [0, 0], "heading": [0]}]})";
  try {
    readPrimitiveFile(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("primitives[0].curvature"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readPrimitiveFile(dir / "missing.json"), InputError);
  EXPECT_THROW(
      loadOrGeneratePrimitives(LatticeSpec{}, models::VehicleLimits{}, {}, dir / "missing.json"),
      InputError);
  LatticeSpec eight;
  eight.heading_count = 8;
  EXPECT_THROW(loadOrGeneratePrimitives(eight, models::VehicleLimits{}, {}, file), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace terratraj::search
