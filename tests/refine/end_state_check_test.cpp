// refine/src/end_state_check: an end state the speed look-ups forbid proves the goal
// unreachable (the verdict checks them at the first and the last rows); within the bound, or
// within the margin the solver's end tolerance needs, it proves nothing.

#include "../../refine/src/end_state_check.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../terrain/test_maps.hpp"
#include "terratraj/bench/robustness_sets.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/velocity_table.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::refine {
namespace {

// The Segway across a 19 deg plane (uphill along x), where its look-ups allow some speed but
// less than 0.5 m/s (they fall to 0 at 20 deg).
class EndStateCheckTest : public ::testing::Test {
 protected:
  EndStateCheckTest()
      : map_(terrain::testing::planeMap(120, 120, 0.25, std::tan(19.0 * M_PI / 180.0), 0.0, 0.0)),
        surface_(map_, terrain::Interpolation::kBicubic),
        vehicle_(surface_),
        lookups_(models::defaultSegwayLookups()) {
    problem_.start = {8.0, 15.0, 0.0, 0.0, 0.0};
    problem_.goal = {14.0, 16.0, 0.0, 0.0, 0.0};
    problem_.limits = bench::problem_sets::roverLimits();
    problem_.tables.segway = &lookups_;
    cap_ = lookups_.bounds.speedLimit(19.0 * M_PI / 180.0);
  }

  terrain::ElevationMap map_;
  terrain::TerrainSurface surface_;
  models::PointAttitudeModel vehicle_;
  models::SegwayLookups lookups_;
  ocp::BoundaryValueProblem problem_;
  double cap_ = 0.0;  ///< the look-ups' speed bound on the plane [m/s]
};

TEST_F(EndStateCheckTest, AGoalFasterThanTheLookUpsAllowIsUnreachable) {
  ASSERT_GT(cap_, 0.1);
  ASSERT_LT(cap_, 0.45);
  problem_.goal.v = 0.5;
  const std::optional<models::GoalReachability> end = detail::checkEndStates(vehicle_, problem_);
  ASSERT_TRUE(end.has_value());
  EXPECT_FALSE(end->reachable);
  EXPECT_NE(end->reason.find("at the goal the vehicle moves at 0.5 m/s on a slope of 19 deg"),
            std::string::npos)
      << end->reason;
  EXPECT_NE(end->reason.find("look-ups allow at most"), std::string::npos) << end->reason;
}

TEST_F(EndStateCheckTest, AStartFasterThanTheLookUpsAllowIsUnreachable) {
  problem_.start.v = 0.5;
  const std::optional<models::GoalReachability> end = detail::checkEndStates(vehicle_, problem_);
  ASSERT_TRUE(end.has_value());
  EXPECT_NE(end->reason.find("at the start the vehicle moves at 0.5 m/s"), std::string::npos)
      << end->reason;
}

TEST_F(EndStateCheckTest, EndsWithinTheBoundOrItsMarginProveNothing) {
  problem_.start.v = 0.95 * cap_;
  problem_.goal.v = 1.005 * cap_;  // within the 1 % the solver's end tolerance may need
  EXPECT_FALSE(detail::checkEndStates(vehicle_, problem_).has_value());
  problem_.goal.v = 0.0;
  EXPECT_FALSE(detail::checkEndStates(vehicle_, problem_).has_value());
}

TEST_F(EndStateCheckTest, ASpeedTableBoundsTheEndsWithoutTheSegway) {
  problem_.tables.segway = nullptr;
  // 0.3 m/s on pitches from 0.2 to 1 rad (the plane's 19 deg is 0.33 rad).
  const models::PitchSpeedTable table(models::BinEdges({-1.0, 0.0, 0.2, 1.0}, "pitch"),
                                      {1.0, 1.0, 0.3});
  problem_.tables.pitch = &table;
  problem_.goal.v = 0.6;
  const std::optional<models::GoalReachability> end = detail::checkEndStates(vehicle_, problem_);
  ASSERT_TRUE(end.has_value());
  EXPECT_NE(end->reason.find("speed tables allow at most"), std::string::npos) << end->reason;
  problem_.goal.v = 0.25;
  EXPECT_FALSE(detail::checkEndStates(vehicle_, problem_).has_value());
}

}  // namespace
}  // namespace terratraj::refine
