// The boundary-value solver end to end, checked by re-simulation (004_... 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "boundary_value_fixtures.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"

namespace terratraj::ocp {
namespace {

TEST(BoundaryValueSolver, FlatFanReachedByNewtonToMillimetres) {
  const terrain::ElevationMap map = fixtures::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  int converged = 0;
  for (const BoundaryValueProblem& problem : fixtures::flatFan()) {
    const BoundaryValueSolution s = solveBoundaryValue(vehicle, problem, {}, &map);
    ASSERT_TRUE(s.verified.ok) << s.verified.message;
    EXPECT_EQ(s.status, SolveStatus::kConverged) << s.reason;
    converged += s.status == SolveStatus::kConverged;
    // Independent re-simulation: the terminal state actually reached.
    EXPECT_LT(s.verified.terminal_error.head<2>().norm(), 1e-3);
    EXPECT_LT(std::abs(s.verified.terminal_error.z()), 1e-3);
    const models::TrajectorySample& last = s.verified.trajectory.samples.back();
    EXPECT_NEAR(last.x, problem.goal.x, 1e-3);
    EXPECT_NEAR(last.y, problem.goal.y, 1e-3);
  }
  EXPECT_EQ(converged, 45);
}

// 004_... fig. 4: >= 95 % of the 94 edges converge on rough terrain with the rocker-bogie,
// most in 5 iterations or fewer.
TEST(BoundaryValueSolver, RoughLatticeWithRockerBogie) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::RockerBogieAttitudeModel vehicle(surface);
  const std::vector<BoundaryValueProblem> lattice = fixtures::roughLattice();
  ASSERT_EQ(lattice.size(), 94u);
  int converged = 0, within_five = 0;
  double max_pitch = 0.0;
  for (const BoundaryValueProblem& problem : lattice) {
    const BoundaryValueSolution s = solveBoundaryValue(vehicle, problem, {}, &map);
    if (s.status == SolveStatus::kConverged) {
      ++converged;
      within_five += s.solver.iterations <= 5;
      EXPECT_LT(s.verified.terminal_error.head<2>().norm(), 1e-3 + 1e-5);
      EXPECT_LT(std::abs(s.verified.terminal_error.z()), 1e-3 + 1e-5);
      max_pitch = std::max(max_pitch, s.verified.max_abs_pitch);
    }
  }
  RecordProperty("converged", converged);
  RecordProperty("within_five_iterations", within_five);
  EXPECT_GE(converged, 90);  // 95 % of 94
  EXPECT_GT(within_five, converged / 2);
  EXPECT_GT(max_pitch, 0.05);  // the terrain is rough enough to matter
}

// 004_... 4.2: as alpha grows, slope dwell falls and t_f grows; alpha = 0 drives straight.
TEST(BoundaryValueSolver, SlopeDwellTradesTimeForAttitude) {
  const terrain::ElevationMap map = fixtures::singleHillMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::RockerBogieAttitudeModel vehicle(surface);
  std::vector<BoundaryValueSolution> solutions;
  for (const double alpha : {0.0, 1.0, 2.0}) {
    solutions.push_back(solveBoundaryValue(vehicle, fixtures::singleHillProblem(alpha), {}, &map));
    ASSERT_EQ(solutions.back().status, SolveStatus::kConverged)
        << "alpha " << alpha << ": " << solutions.back().reason;
  }
  EXPECT_LT(solutions[1].verified.slope_dwell, solutions[0].verified.slope_dwell);
  EXPECT_LT(solutions[2].verified.slope_dwell, solutions[1].verified.slope_dwell);
  EXPECT_GT(solutions[1].verified.final_time, solutions[0].verified.final_time);
  EXPECT_GT(solutions[2].verified.final_time, solutions[1].verified.final_time);
  // alpha = 0: the shortest path is (nearly) straight, over the side of the hill.
  EXPECT_LT(solutions[0].verified.length, 4.0 * 1.01);
  EXPECT_GT(solutions[0].verified.max_abs_roll + solutions[0].verified.max_abs_pitch, 0.1);
}

TEST(BoundaryValueSolver, UnreachableFormsAndBadStatesAreStatusesNotCrashes) {
  const terrain::ElevationMap map = fixtures::flatMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::PointAttitudeModel vehicle(surface);
  // Rest to rest with a linear speed: the vehicle cannot move.
  BoundaryValueProblem still = fixtures::cruise(3, 10, 0, 8, 10, 0);
  still.start.v = still.goal.v = 0.0;
  BoundaryValueSolution s = solveBoundaryValue(vehicle, still, {}, &map);
  EXPECT_EQ(s.status, SolveStatus::kInfeasible);
  EXPECT_NE(s.reason.find("speed"), std::string::npos) << s.reason;
  // Too few unknowns for three terminal constraints.
  BoundaryValueProblem few = fixtures::cruise(3, 10, 0, 8, 11, 0);
  few.orders = {2, 1};
  s = solveBoundaryValue(vehicle, few, {}, &map);
  EXPECT_EQ(s.status, SolveStatus::kInfeasible);
  // NaN in the goal.
  BoundaryValueProblem nan = fixtures::cruise(3, 10, 0, 8, 11, 0);
  nan.goal.x = std::nan("");
  s = solveBoundaryValue(vehicle, nan, {}, &map);
  EXPECT_NE(s.status, SolveStatus::kConverged);
  // Minimum time with a free speed and no limits to hold it: t_f collapses, within the
  // iteration budget.
  BoundaryValueProblem free_speed = fixtures::cruise(3, 10, 0, 8, 11, 0);
  free_speed.orders.speed = 3;
  BoundaryValueOptions options;
  options.max_iterations = 30;
  s = solveBoundaryValue(vehicle, free_speed, options, &map);
  EXPECT_NE(s.status, SolveStatus::kConverged);
  EXPECT_LE(s.solver.iterations, 30);
  // Goal off the map: the path leaves the terrain.
  BoundaryValueProblem off = fixtures::cruise(3, 10, 0, 30, 10, 0);
  s = solveBoundaryValue(vehicle, off, {}, &map);
  EXPECT_NE(s.status, SolveStatus::kConverged);
  EXPECT_FALSE(s.reason.empty());
}

TEST(BoundaryValueSolver, NewtonFdAndNewtonReachTheSameOptimum) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::RockerBogieAttitudeModel vehicle(surface);
  const std::vector<BoundaryValueProblem> lattice = fixtures::roughLattice();
  int compared = 0;
  for (int i = 0; i < 6; ++i) {
    BoundaryValueOptions newton, fd;
    fd.method = BoundaryValueMethod::kNewtonFd;
    const BoundaryValueSolution a = solveBoundaryValue(vehicle, lattice[i], newton, &map);
    const BoundaryValueSolution b = solveBoundaryValue(vehicle, lattice[i], fd, &map);
    if (a.status != SolveStatus::kConverged || b.status != SolveStatus::kConverged) continue;
    ++compared;
    EXPECT_NEAR(a.verified.cost, b.verified.cost, 1e-3 * a.verified.cost) << i;
    EXPECT_GT(b.solver.integrations, a.solver.integrations);
  }
  EXPECT_GE(compared, 5);
}

// The four solvers on one formulation reach the same optimum where they converge (rough
// terrain, rocker-bogie, slope dwell so that the optimum is not at a limit of the form).
TEST(BoundaryValueSolver, AllFourSolversReachTheSameOptimum) {
  const terrain::ElevationMap map = fixtures::roughMap();
  const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
  const models::RockerBogieAttitudeModel vehicle(surface);
  const std::vector<BoundaryValueProblem> lattice = fixtures::roughLattice();
  int agreeing = 0;
  for (int i = 0; i < 4; ++i) {
    BoundaryValueProblem problem = lattice[i];
    problem.cost = {CostKind::kSlopeDwell, 1.0};
    std::vector<double> costs;
    for (const BoundaryValueMethod method :
         {BoundaryValueMethod::kNewton, BoundaryValueMethod::kNewtonFd, BoundaryValueMethod::kIpopt,
          BoundaryValueMethod::kCeres}) {
      BoundaryValueOptions options;
      options.method = method;
      const BoundaryValueSolution s = solveBoundaryValue(vehicle, problem, options, &map);
      if (s.status == SolveStatus::kConverged) costs.push_back(s.verified.cost);
    }
    if (costs.size() < 4) continue;
    ++agreeing;
    const auto [low, high] = std::minmax_element(costs.begin(), costs.end());
    EXPECT_LT(*high - *low, 1e-3 * *low) << "edge " << i;
  }
  EXPECT_GE(agreeing, 3);
}

}  // namespace
}  // namespace terratraj::ocp
