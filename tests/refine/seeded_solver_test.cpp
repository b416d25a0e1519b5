// refine::solveSeeded, the core's default: the robustness set in unit-test size (other seeds
// than `bench convergence`): constant-speed curvature-limited turns within the Dubins band,
// rest-to-rest turn-backs, rest to rest by the parametric ipopt (free speed). Each written
// trajectory is re-checked here, row by row, against the limits and the goal (not by the
// solver's own verdict).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "../terrain/test_maps.hpp"
#include "terratraj/bench/robustness_sets.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/ocp/dubins_path.hpp"
#include "terratraj/refine/search_seed.hpp"
#include "terratraj/refine/seeded_solver.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::refine {
namespace {

namespace sets = bench::problem_sets;

// Every row within the limits (1e-3 relative, as the contract's verdict), the last row at the
// goal within 1e-3 m and the start at the start.
void expectWithinLimitsAndAtGoal(const ocp::BoundaryValueProblem& problem,
                                 const models::Trajectory& trajectory) {
  ASSERT_FALSE(trajectory.samples.empty());
  const models::VehicleLimits& l = problem.limits;
  const double slack = 1.0 + 1e-3;
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    const models::TrajectorySample& s = trajectory.samples[i];
    EXPECT_LE(s.v, l.v_max * slack + 1e-6) << "row " << i + 1;
    EXPECT_LE(std::abs(s.omega), l.omega_max * slack + 1e-6) << "row " << i + 1;
    EXPECT_LE(std::abs(s.curvature), l.kappa_max * slack + 1e-6) << "row " << i + 1;
    if (i > 0) {
      const models::TrajectorySample& p = trajectory.samples[i - 1];
      const double dt = s.t - p.t;
      ASSERT_GT(dt, 0.0) << "row " << i + 1;
      EXPECT_LE(std::abs(s.v - p.v) / dt, l.a_max * slack + 1e-6) << "row " << i + 1;
    }
  }
  const models::TrajectorySample& first = trajectory.samples.front();
  const models::TrajectorySample& last = trajectory.samples.back();
  EXPECT_NEAR(first.x, problem.start.x, 1e-6);
  EXPECT_NEAR(first.y, problem.start.y, 1e-6);
  EXPECT_LT(std::hypot(last.x - problem.goal.x, last.y - problem.goal.y), 1e-3);
  EXPECT_LT(std::abs(std::remainder(last.heading - problem.goal.heading, 2 * M_PI)), 1e-3);
}

class SeededSolverTest : public ::testing::Test {
 protected:
  SeededSolverTest()
      : map_(sets::openFlatMap()),
        surface_(map_, terrain::Interpolation::kBicubic),
        vehicle_(surface_) {}

  SeededSolution solve(const ocp::BoundaryValueProblem& problem, CoreMethod method) const {
    SeededSolveOptions options;
    options.method = method;
    options.time_limit_s = 60.0;
    return solveSeeded(vehicle_, problem, &map_, options);
  }

  // Raises on the map a ridge along x = 15 m (50 deg flanks) ending at y = 18 m, and returns
  // the problem from (8, 8) to (22, 8) across it, rest to rest, the rover's limits.
  ocp::BoundaryValueProblem acrossARidge() {
    terrain::testing::raiseRidge(map_, 15.0, 2.0, 1.0, 18.0, 2.0);
    ocp::BoundaryValueProblem problem;
    problem.start = {8.0, 8.0, 0.0, 0.0, 0.0};
    problem.goal = {22.0, 8.0, 0.0, 0.0, 0.0};
    problem.limits = sets::roverLimits();
    return problem;
  }

  // Makes a block of the map no data, beside the straight route from (6, 5) to (16, 5), and
  // returns that problem, rest to rest, the rover's limits.
  ocp::BoundaryValueProblem besideNoData() {
    for (int row = 21; row <= 40; ++row) {
      for (int col = 36; col <= 44; ++col) map_.elevation()(row, col) = std::nanf("");
    }
    ocp::BoundaryValueProblem problem;
    problem.start = {6.0, 5.0, 0.0, 0.0, 0.0};
    problem.goal = {16.0, 5.0, 0.0, 0.0, 0.0};
    problem.limits = sets::roverLimits();
    return problem;
  }

  terrain::ElevationMap map_;
  terrain::TerrainSurface surface_;
  models::PointAttitudeModel vehicle_;
};

// At 1 m/s with v_max 1 m/s the speed cannot rise: the time is the path's length, at least
// the Dubins length (up to the clothoids of sigma_max); the default is within 10 % of it.
TEST_F(SeededSolverTest, ConstantSpeedTurnsAreWithinTheDubinsBand) {
  for (const ocp::BoundaryValueProblem& problem : sets::constantSpeedTurns(3, 7)) {
    const SeededSolution s = solve(problem, CoreMethod::kAuto);
    ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
    expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
    const double dubins =
        ocp::dubinsPaths({problem.start.x, problem.start.y, problem.start.heading},
                         {problem.goal.x, problem.goal.y, problem.goal.heading}, 1.0)
            .front()
            .length();
    const double duration = s.verified.trajectory.samples.back().t;
    EXPECT_GE(duration / dubins, 0.998);
    EXPECT_LE(duration / dubins, 1.10) << s.initial_guess;
  }
}

// Rest to rest, the goal behind the start: the speed rises and returns to 0.
TEST_F(SeededSolverTest, RestToRestTurnBacksConverge) {
  for (const ocp::BoundaryValueProblem& problem : sets::turnBacks(2, 7)) {
    const SeededSolution s = solve(problem, CoreMethod::kAuto);
    ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
    EXPECT_EQ(s.method, "collocation");
    expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
    double top = 0.0;
    for (const models::TrajectorySample& row : s.verified.trajectory.samples) {
      top = std::max(top, row.v);
    }
    EXPECT_GT(top, 0.5);  // not crawling: a_max 0.5 m/s^2 over 2-5 m allows about 1 m/s
  }
}

// The seeds as a portfolio: with a first budget far too small for any solve, every seed is
// cut, and tried again with twice the budget, round after round, until one converges; each
// attempt reports the budget it ran in.
TEST_F(SeededSolverTest, SeedsCutByTheirBudgetAreRetriedWithTwiceIt) {
  const ocp::BoundaryValueProblem problem = sets::turnBacks(1, 7).front();
  SeededSolveOptions options;
  options.time_limit_s = 120.0;
  options.seed_time_s = 1e-3;
  options.first_seed_time_s = 2e-3;
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
  expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
  ASSERT_GE(s.attempts.size(), 2u);
  EXPECT_EQ(s.attempts.front().round, 0);
  EXPECT_GT(s.attempts.back().round, 0);
  for (const SeedAttempt& a : s.attempts) {
    // The first seed's chain: its attempts, and collocation "ipopt from" it.
    const bool first = a.seed.find(s.attempts.front().seed) != std::string::npos;
    const double base = first ? options.first_seed_time_s : options.seed_time_s;
    EXPECT_DOUBLE_EQ(a.budget_s, base * std::ldexp(1.0, a.round)) << a.seed;
  }
  // The rounds in order: a seed is retried only after every seed has had its budget.
  for (std::size_t i = 1; i < s.attempts.size(); ++i) {
    EXPECT_GE(s.attempts[i].round, s.attempts[i - 1].round);
  }
}

// Near the solve's deadline a seed's doubled budget is capped by the time left, and a seed the
// clock cut is tried again only with more time than it had: with less, its chain would end as
// it did or sooner. The first word's budget here is most of the time left after the first
// round (each word's chain is cut by the clock in it), so without the rule the first word was
// tried again with less time than it had. (In a slow build the first round can use the whole
// limit; nothing is tried again then.)
TEST_F(SeededSolverTest, ACutSeedIsTriedAgainOnlyWithMoreTimeThanBefore) {
  const ocp::BoundaryValueProblem problem = sets::turnBacks(1, 7).front();
  SeededSolveOptions options;
  options.time_limit_s = 0.25;
  options.first_seed_time_s = 0.1;
  options.seed_time_s = 0.01;
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_GE(s.attempts.size(), 2u);
  std::map<std::string, const SeedAttempt*> last;  // per seed and step
  for (const SeedAttempt& a : s.attempts) {
    EXPECT_LE(a.time_given_s, a.budget_s) << a.seed;
    EXPECT_LE(a.time_given_s, *options.time_limit_s) << a.seed;
    const auto it = last.find(a.seed);
    if (it != last.end() && it->second->round < a.round) {
      // 1 ms: the time left is read again when the chain starts.
      EXPECT_GT(a.time_given_s, it->second->time_given_s - 1e-3)
          << a.seed << " in round " << a.round << " after round " << it->second->round;
    }
    last[a.seed] = &a;
  }
  if (s.status != ocp::SolveStatus::kConverged) {
    EXPECT_TRUE(s.time_limit_reached) << s.reason;
    EXPECT_NE(s.reason.find("time limit of 0.25 s"), std::string::npos) << s.reason;
  }
}

// A word whose steps end on their own (here at iteration caps far too small to converge) is
// not retried: with more time its deterministic steps would end the same; and the transcriptions
// and the parametric solvers say when the clock, not a cap, stopped them.
TEST_F(SeededSolverTest, StepsThatEndedOnTheirOwnAreNotRetried) {
  const ocp::BoundaryValueProblem problem = sets::turnBacks(1, 7).front();
  SeededSolveOptions options;
  options.time_limit_s = 120.0;
  options.seed_time_s = 60.0;
  options.transcription.transcription.max_iterations = 2;
  options.ipopt_max_iterations = 2;
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_NE(s.status, ocp::SolveStatus::kConverged);
  EXPECT_FALSE(s.time_limit_reached);
  ASSERT_GE(s.attempts.size(), 2u);
  for (const SeedAttempt& a : s.attempts) {
    EXPECT_EQ(a.round, 0) << a.seed << ": " << a.reason;
    EXPECT_EQ(a.reason.find("time limit"), std::string::npos) << a.seed << ": " << a.reason;
  }
  // Budgets the clock cuts (some steps of a chain end on their own within them, some not):
  // cut words are retried, and a retry repeats a step (a seed and method) only if the clock
  // stopped it before.
  options.seed_time_s = 0.02;
  options.first_seed_time_s = 0.02;
  options.time_limit_s = 1.0;
  const SeededSolution cut = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_NE(cut.status, ocp::SolveStatus::kConverged);
  EXPECT_GT(cut.attempts.back().round, 0);
  EXPECT_TRUE(std::any_of(cut.attempts.begin(), cut.attempts.end(),
                          [](const SeedAttempt& a) { return a.time_limit_reached; }));
  for (std::size_t i = 0; i < cut.attempts.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const SeedAttempt &earlier = cut.attempts[j], &later = cut.attempts[i];
      if (earlier.seed == later.seed && earlier.method == later.method) {
        EXPECT_TRUE(earlier.time_limit_reached)
            << later.seed << " by " << later.method << " repeated in round " << later.round
            << " after ending on its own: " << earlier.reason;
      }
    }
  }
}

// When the solve's own clock ends the rounds (here a limit of 0 s: the first seed is tried and
// cut at once), the result says so: time_limit_reached, and a reason naming the limit beside the
// best attempt's own.
TEST_F(SeededSolverTest, ASolveItsTimeLimitEndsSaysSo) {
  const ocp::BoundaryValueProblem problem = sets::turnBacks(1, 7).front();
  SeededSolveOptions options;
  options.time_limit_s = 0.0;
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_NE(s.status, ocp::SolveStatus::kConverged);
  ASSERT_EQ(s.attempts.size(), 1u);
  EXPECT_TRUE(s.time_limit_reached);
  EXPECT_NE(s.reason.find("the solve's time limit of 0 s ran out in round 0"), std::string::npos)
      << s.reason;
}

// The parametric ipopt leaves the speed free (speed order 3) and holds v_max and a_max: the
// smallest rest-to-rest problem is solved.
TEST_F(SeededSolverTest, ParametricIpoptSolvesRestToRest) {
  ocp::BoundaryValueProblem problem;
  problem.start = {10.0, 10.0, 0.0, 0.0, 0.0};
  problem.goal = {16.0, 11.0, 0.3, 0.0, 0.0};
  problem.limits = sets::roverLimits();
  const SeededSolution s = solve(problem, CoreMethod::kIpopt);
  ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
  expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
  ASSERT_TRUE(s.parametric.has_value());
}

// Rest-to-rest turn-backs by the parametric ipopt: at an end at rest the curvature is
// omega' / v', held by its own rows; a limit broken between path points is solved again with
// more points. Every row of the written trajectory holds the limits (checked here).
TEST_F(SeededSolverTest, ParametricIpoptHoldsTheCurvatureOfTurnBacksAtRest) {
  for (const ocp::BoundaryValueProblem& problem : sets::turnBacks(2, 11)) {
    const SeededSolution s = solve(problem, CoreMethod::kIpopt);
    ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
    ASSERT_TRUE(s.parametric.has_value());
    expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
  }
}

// A U-turn where it stands (same position, heading + 180 deg, rest to rest): a valid problem,
// solved by a loop within the curvature limit.
TEST_F(SeededSolverTest, UTurnAtTheSamePositionIsSolved) {
  ocp::BoundaryValueProblem problem;
  problem.start = {15.0, 15.0, 0.0, 0.0, 0.0};
  problem.goal = {15.0, 15.0, M_PI, 0.0, 0.0};
  problem.limits = sets::roverLimits();
  const SeededSolution s = solve(problem, CoreMethod::kAuto);
  ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
  expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
  EXPECT_GT(s.verified.length, M_PI);  // at least half a circle of radius 1 m
}

// A goal boxed in by lethal cells: `infeasible` with the reason, before any seed is tried (the
// reachability check); without the check, after the seeds, within the time limit.
TEST_F(SeededSolverTest, BoxedInGoalIsInfeasibleWithItsReason) {
  terrain::GridLayer& lethal = map_.addLayer(terrain::layer_names::kLethal);
  for (int row = 60; row <= 80; ++row) {
    for (int col = 60; col <= 80; ++col) {
      const bool wall = row <= 62 || row >= 78 || col <= 62 || col >= 78;
      if (wall) lethal(row, col) = 1.0f;
    }
  }
  ocp::BoundaryValueProblem problem;
  problem.start = {5.0, 5.0, 0.0, 0.0, 0.0};
  problem.goal = {17.5, 17.5, 0.0, 0.0, 0.0};  // the box's centre (cells 60-80 of 0.25 m)
  problem.limits = sets::roverLimits();
  SeededSolveOptions options;
  options.time_limit_s = 20.0;
  const SeededSolution checked = solveSeeded(vehicle_, problem, &map_, options);
  EXPECT_EQ(checked.status, ocp::SolveStatus::kInfeasible) << checked.reason;
  EXPECT_NE(checked.reason.find("cannot be reached"), std::string::npos) << checked.reason;
  EXPECT_NE(checked.reason.find("lethal cells"), std::string::npos) << checked.reason;
  EXPECT_TRUE(checked.attempts.empty());
  ASSERT_TRUE(checked.reachability.has_value());
  EXPECT_FALSE(checked.reachability->reachable);

  options.reachability.reset();
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  EXPECT_EQ(s.status, ocp::SolveStatus::kInfeasible) << s.reason;
  EXPECT_NE(s.reason.find("impassable"), std::string::npos) << s.reason;
  EXPECT_LT(s.total_time_ms, 21000.0);
  EXPECT_FALSE(s.reachability.has_value());
}

// A U-turn out of a dead end narrower than the turning circle (issue 17: "turning radius
// larger than the map allows"): `infeasible` with the reason before any seed, by the curvature
// check; a start heading out of it is solved.
TEST_F(SeededSolverTest, AUTurnInADeadEndNarrowerThanTheTurningCircleIsInfeasibleAtOnce) {
  terrain::GridLayer& lethal = map_.addLayer(terrain::layer_names::kLethal);
  // A corridor 1 m wide along x (rows 58-61 free, 57 and 62 walls) closed at x = 12 (column 48);
  // kappa_max 1: a turning circle 2 m across.
  for (int col = 0; col <= 48; ++col) {
    lethal(57, col) = lethal(62, col) = 1.0f;
    if (col == 48) {
      for (int row = 57; row <= 62; ++row) lethal(row, col) = 1.0f;
    }
  }
  ocp::BoundaryValueProblem problem;
  problem.start = {10.5, 15.0, 0.0, 0.0, 0.0};
  problem.goal = {8.0, 15.0, M_PI, 0.0, 0.0};
  problem.limits = sets::roverLimits();
  SeededSolveOptions options;
  options.time_limit_s = 20.0;
  const SeededSolution s = solveSeeded(vehicle_, problem, &map_, options);
  EXPECT_EQ(s.status, ocp::SolveStatus::kInfeasible) << s.reason;
  EXPECT_NE(s.reason.find("leave the start's pose"), std::string::npos) << s.reason;
  EXPECT_TRUE(s.attempts.empty());
  EXPECT_LT(s.total_time_ms, 5000.0);
  problem.start.heading = M_PI;
  problem.goal.x = 5.0;
  const SeededSolution out = solveSeeded(vehicle_, problem, &map_, options);
  EXPECT_EQ(out.status, ocp::SolveStatus::kConverged) << out.reason;
}

// An open problem passes the check (reachable, decided) and is solved as before.
TEST_F(SeededSolverTest, AReachableGoalPassesTheCheckAndIsSolved) {
  ocp::BoundaryValueProblem problem;
  problem.start = {5.0, 5.0, 0.0, 0.0, 0.0};
  problem.goal = {12.0, 9.0, 1.0, 0.0, 0.0};
  problem.limits = sets::roverLimits();
  const SeededSolution s = solve(problem, CoreMethod::kAuto);
  ASSERT_TRUE(s.reachability.has_value());
  EXPECT_TRUE(s.reachability->reachable);
  EXPECT_TRUE(s.reachability->decided);
  EXPECT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
}

// No data beside the straight route (gully_problem.yaml's shoulder in small): the cells under
// every Dubins word hold data, but the bicubic surface is undefined along them (its stencil
// reaches the no-data cells). The words are dropped before any solve, the search seed goes
// round, and its refinement keeps where the surface is defined.
TEST_F(SeededSolverTest, NoDataBesideTheWordsLeavesItToTheSearchSeed) {
  const ocp::BoundaryValueProblem problem = besideNoData();
  const SeededSolution s = solve(problem, CoreMethod::kAuto);
  EXPECT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
  for (const SeedAttempt& a : s.attempts) {
    EXPECT_EQ(a.reason.find("cannot be placed"), std::string::npos) << a.seed << ": " << a.reason;
  }
  ASSERT_FALSE(s.attempts.empty());
  EXPECT_NE(s.attempts.back().seed.find("search"), std::string::npos) << s.attempts.back().seed;
  for (const models::TrajectorySample& row : s.verified.trajectory.samples) {
    EXPECT_TRUE(surface_.height({row.x, row.y}).has_value()) << row.x << ", " << row.y;
  }
  expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
}

// A ridge steeper than the pitch and roll limits across every Dubins word, with a gap to the
// north (the moon DEM's slopes in small): the words are left until after the search seed,
// whose route goes round; started across the slope, collocation wandered (moon, 57 m: 60 s,
// not converged, versus 1.1 s from the search seed). The attitude along the result is
// re-computed here, row by row.
TEST_F(SeededSolverTest, WordsAcrossSlopesBeyondTheLimitsComeAfterTheSearchSeed) {
  const ocp::BoundaryValueProblem problem = acrossARidge();
  const SeededSolution s = solve(problem, CoreMethod::kAuto);
  ASSERT_EQ(s.status, ocp::SolveStatus::kConverged) << s.reason;
  ASSERT_FALSE(s.attempts.empty());
  EXPECT_NE(s.attempts.front().seed.find("search"), std::string::npos) << s.attempts.front().seed;
  // The seed's name reports the PRM's budget: the default 10 s (the first seed's budget is
  // first_seed_time_s, 30 s, and the PRM gets at most half of it).
  EXPECT_NE(s.attempts.front().seed.find(" s of 10 s"), std::string::npos)
      << s.attempts.front().seed;
  expectWithinLimitsAndAtGoal(problem, s.verified.trajectory);
  models::AttitudeWorkspace workspace;
  models::AttitudeResult placed;
  const double slack = 1.0 + 1e-3;
  for (const models::TrajectorySample& row : s.verified.trajectory.samples) {
    ASSERT_EQ(vehicle_.compute({row.x, row.y, row.heading}, workspace, placed),
              models::AttitudeStatus::kOk);
    EXPECT_LE(std::abs(placed.attitude.pitch), problem.limits.pitch_max * slack) << row.t;
    EXPECT_LE(std::abs(placed.attitude.roll), problem.limits.roll_max * slack) << row.t;
  }
  // It went round: north of the gap.
  double north = 0.0;
  for (const models::TrajectorySample& row : s.verified.trajectory.samples) {
    north = std::max(north, row.y);
  }
  EXPECT_GT(north, 18.0);
}

// The search seed's refinement keeps the PRM route's class: here round the ridge's end, more
// than 1.5x the time a word across it could take. After it converged the word is tried too
// (retry_cost_ratio), and the better verified result kept; with the ratio out of reach, the
// search seed's result alone.
TEST_F(SeededSolverTest, ASearchSeedsDetourStillTriesTheWords) {
  const ocp::BoundaryValueProblem problem = acrossARidge();
  SeededSolveOptions options;
  options.time_limit_s = 60.0;
  options.max_words = 1;
  options.seed_time_s = 0.5;  // the word's chain: it crosses the ridge and cannot converge
  const SeededSolution tried = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_EQ(tried.status, ocp::SolveStatus::kConverged) << tried.reason;
  ASSERT_GE(tried.attempts.size(), 2u);
  EXPECT_NE(tried.attempts.front().seed.find("search"), std::string::npos);
  EXPECT_EQ(tried.attempts.front().status, ocp::SolveStatus::kConverged);
  EXPECT_NE(tried.attempts[1].seed.find("dubins"), std::string::npos) << tried.attempts[1].seed;
  EXPECT_EQ(tried.attempts[1].round, 0);
  const double word_time = 14.0 / problem.limits.v_max;  // the straight word, at least
  EXPECT_GT(tried.verified.cost, options.retry_cost_ratio * word_time);  // hence the retry

  options.retry_cost_ratio = 1e9;
  const SeededSolution alone = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_EQ(alone.status, ocp::SolveStatus::kConverged) << alone.reason;
  ASSERT_EQ(alone.attempts.size(), 1u);
  EXPECT_NEAR(alone.verified.cost, tried.verified.cost, 1e-9);  // the word did not beat it
}

// A Segway on a slope its look-ups allow no speed on (22 deg along its heading; they end at
// 20 deg) can never leave the start: unreachable, with the reason, before any seed. The same
// start at 15 deg is solved, and the result holds the look-ups (the verdict checks them).
TEST(SeededSolverSegway, AStartOnASlopeItCannotDriveIsUnreachable) {
  const models::SegwayLookups lookups = models::defaultSegwayLookups();
  const auto solveOn = [&](double slope_deg) {
    const terrain::ElevationMap map =
        terrain::testing::planeMap(120, 120, 0.25, std::tan(slope_deg * M_PI / 180.0), 0.0, 0.0);
    const terrain::TerrainSurface surface(map, terrain::Interpolation::kBicubic);
    const models::PointAttitudeModel vehicle(surface);
    ocp::BoundaryValueProblem problem;
    problem.start = {8.0, 15.0, 0.0, 0.0, 0.0};
    problem.goal = {14.0, 16.0, 0.0, 0.0, 0.0};
    problem.limits = sets::roverLimits();
    problem.tables.segway = &lookups;
    SeededSolveOptions options;
    options.time_limit_s = 60.0;
    return solveSeeded(vehicle, problem, &map, options);
  };
  const SeededSolution stuck = solveOn(22.0);
  EXPECT_EQ(stuck.status, ocp::SolveStatus::kInfeasible);
  ASSERT_TRUE(stuck.reachability.has_value());
  EXPECT_FALSE(stuck.reachability->reachable);
  EXPECT_NE(stuck.reason.find("at the start the Segway stands on a slope of 22 deg"),
            std::string::npos)
      << stuck.reason;
  EXPECT_TRUE(stuck.attempts.empty());
  const SeededSolution drivable = solveOn(15.0);
  ASSERT_EQ(drivable.status, ocp::SolveStatus::kConverged) << drivable.reason;
  EXPECT_TRUE(drivable.verdict.passes()) << drivable.verdict.reason;
}

// When the refinement of the PRM's first solution fails on its own (here: Ipopt held to 2
// iterations), the PRM continues for search_improve_milestones and its better route is
// refined, up to search_improvements times. The seed's name says which route, the reason what
// became of the earlier ones. With no continuation, the first route's verdict stands. (On this
// map the PRM's route improves within 200 milestones of its first solution and again within
// the next 200, then not within 200 more.)
TEST_F(SeededSolverTest, AFailedRefinementOfTheSearchSeedRefinesThePrmsBetterRoute) {
  const ocp::BoundaryValueProblem problem = besideNoData();
  SeededSolveOptions options;
  options.transcription.transcription.max_iterations = 2;
  options.search_improve_milestones = 200;
  options.search_improvements = 0;
  const SeededSolution first = solveFromSearch(vehicle_, problem, map_, options, 60.0, "a test");
  EXPECT_NE(first.status, ocp::SolveStatus::kConverged);
  EXPECT_FALSE(first.time_limit_reached);
  EXPECT_EQ(first.initial_guess.rfind("search (prm first solution, ", 0), 0u);
  EXPECT_EQ(first.initial_guess.find("milestones"), std::string::npos) << first.initial_guess;
  EXPECT_EQ(first.reason.find("before it"), std::string::npos) << first.reason;

  options.search_improvements = 3;
  const SeededSolution later = solveFromSearch(vehicle_, problem, map_, options, 60.0, "a test");
  EXPECT_NE(later.status, ocp::SolveStatus::kConverged);
  EXPECT_FALSE(later.time_limit_reached);
  EXPECT_NE(later.initial_guess.find("; its best route after 400 more milestones, "),
            std::string::npos)
      << later.initial_guess;
  const std::size_t before_first = later.reason.find("; before it, search (prm first solution, ");
  const std::size_t before_second = later.reason.find("after 200 more milestones, ");
  EXPECT_NE(before_first, std::string::npos) << later.reason;
  EXPECT_NE(before_second, std::string::npos) << later.reason;
  EXPECT_LT(before_first, before_second);  // in the order they were refined
}

// After a word converged, the search seed is tried in the first round, after the words, when
// the best cost is above retry_cost_ratio x the shortest word's bang-bang time (a word's detour
// round a slope the PRM's route passes); not with the ratio out of reach.
TEST_F(SeededSolverTest, AWordsDetourAlsoTriesTheSearchSeed) {
  ocp::BoundaryValueProblem problem;
  problem.start = {8.0, 8.0, 0.0, 0.0, 0.0};
  problem.goal = {14.0, 12.0, M_PI / 2, 0.0, 0.0};
  problem.limits = sets::roverLimits();
  SeededSolveOptions options;
  options.time_limit_s = 60.0;
  options.max_words = 1;
  options.retry_cost_ratio = 1.0;  // any cost above the word's bang-bang time
  const SeededSolution tried = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_EQ(tried.status, ocp::SolveStatus::kConverged) << tried.reason;
  ASSERT_GE(tried.attempts.size(), 2u);
  EXPECT_NE(tried.attempts.front().seed.find("dubins"), std::string::npos);
  EXPECT_EQ(tried.attempts.front().status, ocp::SolveStatus::kConverged);
  EXPECT_NE(tried.attempts.back().seed.find("search"), std::string::npos)
      << tried.attempts.back().seed;
  EXPECT_EQ(tried.attempts.back().round, 0);
  // Improving on a result, it refines the PRM's route search_improve_milestones on
  // (RouteOrder::kImprovedFirst), not its first solution.
  EXPECT_NE(tried.attempts.back().seed.find("; its best route after 8000 more milestones"),
            std::string::npos)
      << tried.attempts.back().seed;
  expectWithinLimitsAndAtGoal(problem, tried.verified.trajectory);

  options.retry_cost_ratio = 1.5;
  const SeededSolution kept = solveSeeded(vehicle_, problem, &map_, options);
  ASSERT_EQ(kept.status, ocp::SolveStatus::kConverged) << kept.reason;
  for (const SeedAttempt& a : kept.attempts) {
    EXPECT_EQ(a.seed.find("search"), std::string::npos) << a.seed;
  }
  EXPECT_LE(tried.verified.cost, kept.verified.cost + 1e-9);  // the better result kept
}

// The search seed's budget: absent, kDefaultSearchTimeS (the moon four-wheel problem of
// docs/benchmarks.md failed with a fixed 1 s when the PRM needed more); never more than half the
// time left, which the refinement of its path needs.
TEST(SearchSeedBudget, DefaultsToTenSecondsAndLeavesHalfTheTimeLeft) {
  SeededSolveOptions options;
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, std::nullopt), kDefaultSearchTimeS);
  EXPECT_DOUBLE_EQ(kDefaultSearchTimeS, 10.0);
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, 60.0), 10.0);
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, 6.0), 3.0);
  options.search_time_s = 1.0;
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, std::nullopt), 1.0);
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, 1.0), 0.5);
  options.search_time_s = 0.0;
  EXPECT_DOUBLE_EQ(searchSeedBudget(options, 60.0), 0.0);
}

}  // namespace
}  // namespace terratraj::refine
