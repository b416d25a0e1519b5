#include "terratraj/models/kinodynamic_tables.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/finite_difference.hpp"
#include "terratraj/models/driving_log_simulator.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

fs::path writeFile(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("terratraj_tables_" + name);
  std::ofstream(path) << text;
  return path;
}

TEST(BinEdges, FindsBinsAndClampsOutside) {
  const BinEdges edges({-0.5, -0.25, 0.0, 0.25, 0.5}, "pitch");
  EXPECT_EQ(edges.binCount(), 4);
  EXPECT_EQ(edges.binOf(-0.3), 0);
  EXPECT_EQ(edges.binOf(0.0), 2);  // an edge belongs to the bin above it
  EXPECT_EQ(edges.binOf(0.49), 3);
  EXPECT_EQ(edges.binOf(-9.0), 0);
  EXPECT_EQ(edges.binOf(9.0), 3);
  EXPECT_EQ(edges.binOf(0.5), 3);
  EXPECT_THAT(errorOf([] {
                BinEdges({0.0, 0.0, 1.0}, "roll");
              }),
              HasSubstr("roll: edges must increase strictly"));
  EXPECT_THAT(errorOf([] { BinEdges({0.0}, "roll"); }), HasSubstr("at least two edges"));
  EXPECT_THAT(errorOf([] { BinEdges({0.0, std::nan("")}, "roll"); }), HasSubstr("finite"));
}

TEST(PitchSpeedTable, LooksUpByBinAndSmoothly) {
  // The contract's example.
  const PitchSpeedTable table(BinEdges({-0.5, -0.25, 0.0, 0.25, 0.5}, "pitch"),
                              {3.0, 4.0, 4.0, 2.0});
  EXPECT_EQ(table.lookup(-0.3), 3.0);
  EXPECT_EQ(table.lookup(0.1), 4.0);
  EXPECT_EQ(table.lookup(0.3), 2.0);
  EXPECT_EQ(table.lookup(-2.0), 3.0);  // nearest bin outside
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(table.smoothLookup(table.pitchEdges().centre(i)),
                table.vMax()[static_cast<std::size_t>(i)], 1e-12);
  }
  for (double p = -0.6; p < 0.6; p += 0.0137) {
    double d = 0.0;
    const double v = table.smoothLookup(p, &d);
    const double fd = (table.smoothLookup(p + 1e-7) - table.smoothLookup(p - 1e-7)) / 2e-7;
    EXPECT_NEAR(d, fd, 1e-5) << p;
    EXPECT_GE(v, 0.0);
  }
  // C1 at a centre (where the cubic pieces meet).
  double left = 0.0, right = 0.0;
  table.smoothLookup(-0.125 - 1e-10, &left);
  table.smoothLookup(-0.125 + 1e-10, &right);
  EXPECT_NEAR(left, right, 1e-6);
  EXPECT_THAT(errorOf([] {
                PitchSpeedTable(BinEdges({0, 1}, "p"), {1.0, 2.0});
              }),
              HasSubstr("2 values for 1 bins"));
  EXPECT_THAT(errorOf([] { PitchSpeedTable(BinEdges({0, 1}, "p"), {-1.0}); }), HasSubstr(">= 0"));
}

TEST(RollCurvatureSpeedTable, SmoothLookupHasTheRightGradient) {
  Eigen::MatrixXd v(3, 4);
  v << 1, 2, 3, 2, 4, 5, 6, 5, 2, 1, 0, 0;
  const RollCurvatureSpeedTable table(BinEdges({-0.3, -0.1, 0.1, 0.3}, "roll"),
                                      BinEdges({-1.0, -0.5, 0.0, 0.5, 1.0}, "curvature"), v);
  EXPECT_EQ(table.lookup(0.0, 0.2), 6.0);
  EXPECT_EQ(table.lookup(0.5, -3.0), 2.0);
  EXPECT_NEAR(table.smoothLookup(0.2, 0.75), 0.0, 1e-12);
  for (double r = -0.35; r < 0.35; r += 0.031) {
    for (double k = -1.1; k < 1.1; k += 0.093) {
      double dr = 0.0, dk = 0.0;
      table.smoothLookup(r, k, &dr, &dk);
      const auto speed = [&](const Eigen::VectorXd& at) {
        return Eigen::VectorXd::Constant(1, table.smoothLookup(at(0), at(1)));
      };
      EXPECT_TRUE(terratraj::testing::matchesFiniteDifferences(
          Eigen::RowVector2d(dr, dk),
          terratraj::testing::centralDifferences(speed, Eigen::Vector2d(r, k), 1e-7), 1e-4))
          << "roll " << r << ", curvature " << k;
    }
  }
}

TEST(VelocityTableJson, RoundTripsAndRejectsBadFiles) {
  const PitchSpeedTable pitch(BinEdges({-0.5, -0.25, 0.0, 0.25, 0.5}, "pitch"),
                              {3.0, 4.0, 4.0, 2.0});
  const fs::path file = fs::temp_directory_path() / "terratraj_tables_pitch.json";
  writeTable(pitch, file);
  EXPECT_EQ(readTableKind(file), "pitch");
  EXPECT_EQ(readPitchTable(file).vMax(), pitch.vMax());
  EXPECT_THAT(errorOf([&] { readRollCurvatureTable(file); }),
              HasSubstr("kind: expected \"roll_curvature\""));
  const fs::path contract = writeFile(
      "rc.json",
      R"({"kind": "roll_curvature", "roll_edges_rad": [-0.2, 0, 0.2], "curvature_edges": [-1, 0, 1], "v_max": [[1, 2], [3, 4]]})");
  EXPECT_EQ(readRollCurvatureTable(contract).lookup(0.1, -0.5), 3.0);
  EXPECT_THAT(errorOf([] { readPitchTable(writeFile("a.json", "{not json")); }),
              HasSubstr("not valid JSON"));
  EXPECT_THAT(
      errorOf([] { readPitchTable(writeFile("b.json", R"({"kind": "pitch", "v_max": [1]})")); }),
      HasSubstr("pitch_edges_rad: missing"));
  EXPECT_THAT(errorOf([] {
                readPitchTable(writeFile(
                    "c.json", R"({"kind": "pitch", "pitch_edges_rad": [0, -1], "v_max": [1]})"));
              }),
              HasSubstr("edges must increase strictly"));
  EXPECT_THAT(errorOf([] {
                readPitchTable(writeFile(
                    "d.json", R"({"kind": "pitch", "pitch_edges_rad": [0, 1, 2], "v_max": [1]})"));
              }),
              HasSubstr("1 values for 2 bins"));
  EXPECT_THAT(
      errorOf([] {
        readRollCurvatureTable(writeFile(
            "e.json",
            R"({"kind": "roll_curvature", "roll_edges_rad": [0, 1], "curvature_edges": [0, 1, 2], "v_max": [[1]]})"));
      }),
      HasSubstr("v_max[0]: must hold 2 numbers"));
  EXPECT_THAT(errorOf([] { readTableKind(writeFile("f.json", R"({"kind": "yaw"})")); }),
              HasSubstr("not a table kind"));
  EXPECT_THAT(errorOf([] { readPitchTable("/nonexistent/t.json"); }),
              HasSubstr("cannot be opened"));
}

TEST(PhysicsTables, FollowAppendixOneByHand) {
  const PhysicsTableParameters p;  // g 9.81, half track 0.6, COG 0.8, friction 0.6, length 2.5
  // Level: F = g mu, v = sqrt(2 F (2 L) cos 0) = sqrt(2 * 9.81 * 0.6 * 5).
  EXPECT_NEAR(physicsPitchLimit(0.0, p), std::sqrt(2 * 9.81 * 0.6 * 5.0), 1e-12);
  // Uphill helps braking (pitch > 0 nose up here), downhill hurts.
  EXPECT_GT(physicsPitchLimit(0.2, p), physicsPitchLimit(-0.2, p));
  EXPECT_EQ(physicsPitchLimit(-0.6, p), 0.0);  // tan(0.6) > mu: cannot stop
  // Eq. 1 at zero roll: sqrt(g * half_track / (kappa * COG_z)).
  EXPECT_NEAR(physicsRollCurvatureLimit(0.0, 0.5, p), std::sqrt(9.81 * 0.6 / (0.5 * 0.8)), 1e-12);
  EXPECT_EQ(physicsRollCurvatureLimit(0.3, 0.0, p), 12.0);  // straight: the cap
  // A left turn with the left side high (roll > 0) is worse than with the right side high.
  EXPECT_LT(physicsRollCurvatureLimit(0.2, 0.5, p), physicsRollCurvatureLimit(-0.2, 0.5, p));
  EXPECT_EQ(physicsRollCurvatureLimit(0.2, 0.5, p), physicsRollCurvatureLimit(-0.2, -0.5, p));
  const PitchSpeedTable table = physicsPitchTable(defaultPitchEdges(), p);
  EXPECT_EQ(table.vMax().size(), 16u);
  EXPECT_NEAR(table.vMax()[8], physicsPitchLimit(0.025, p), 1e-12);
}

TEST(DataTables, TopOnePercentPerBinByHand) {
  DrivingStates states;
  // 150 samples in pitch bin 1 (speeds 1..150), 3 in bin 3 (speeds 2, 7, 5), none in bin 2.
  for (int i = 1; i <= 150; ++i) {
    states.pitch.push_back(-0.1);
    states.speed.push_back(i);
  }
  for (const double s : {2.0, 7.0, 5.0}) {
    states.pitch.push_back(0.3);
    states.speed.push_back(s);
  }
  states.roll.assign(states.pitch.size(), 0.0);
  states.curvature.assign(states.pitch.size(), 0.0);
  const BinEdges edges({-0.5, -0.25, 0.0, 0.25, 0.5}, "pitch");
  const PitchSpeedTable table = dataPitchTable(states, edges, DataTableOptions{});
  // Bin 1: the top ceil(1.5) = 2 speeds, (150 + 149) / 2. Bin 3: the top one, 7. Others empty.
  EXPECT_EQ(table.vMax(), (std::vector<double>{0.0, 149.5, 0.0, 7.0}));
  DataTableOptions fill;
  fill.fill_empty = true;
  // Bin 2 lies between filled bins 1 and 3: their mean; bin 0 is outside them and stays 0.
  EXPECT_EQ(dataPitchTable(states, edges, fill).vMax(),
            (std::vector<double>{0.0, 149.5, 78.25, 7.0}));
  DataTableOptions half;
  half.top_fraction = 0.5;
  EXPECT_EQ(dataPitchTable(states, edges, half).vMax()[3], 6.0);  // top 2 of {2, 7, 5}
  half.top_fraction = 0.0;
  EXPECT_THROW(dataPitchTable(states, edges, half), InputError);
}

TEST(DataTables, ViolationFractionsByHand) {
  const PitchSpeedTable pitch(BinEdges({-1.0, 0.0, 1.0}, "pitch"), {2.0, 1.0});
  Eigen::MatrixXd v(1, 2);
  v << 3.0, 0.5;
  const RollCurvatureSpeedTable rc(BinEdges({-1, 1}, "roll"), BinEdges({-1, 0, 1}, "curvature"), v);
  DrivingStates states;
  // (pitch, curvature, speed): limits pitch 2|1, rc 3|0.5.
  const double rows[4][3] = {{-0.5, -0.5, 1.5},  // ok, ok
                             {0.5, -0.5, 1.5},   // pitch (1.5 > 1), ok
                             {-0.5, 0.5, 1.0},   // ok, rc (1 > 0.5)
                             {0.5, 0.5, 2.5}};   // both
  for (const auto& r : rows) {
    states.pitch.push_back(r[0]);
    states.curvature.push_back(r[1]);
    states.speed.push_back(r[2]);
    states.roll.push_back(0.0);
  }
  const ViolationReport report = analyseViolations(states, &pitch, &rc);
  EXPECT_EQ(report.states, 4u);
  EXPECT_DOUBLE_EQ(*report.pitch_fraction, 0.5);
  EXPECT_DOUBLE_EQ(*report.roll_curvature_fraction, 0.5);
  EXPECT_DOUBLE_EQ(report.combined_fraction, 0.75);
  EXPECT_DOUBLE_EQ(report.max_excess, 2.0);
  EXPECT_FALSE(analyseViolations(states, nullptr, &rc).pitch_fraction.has_value());
}

TEST(DrivingLogSimulator, TheAvoidedRegionStaysEmptyAndTheRestIsFast) {
  DrivingLogOptions options;
  options.duration = 900.0;
  const Trajectory log = simulateDrivingLog(options);
  EXPECT_EQ(log.samples.size(), 9001u);
  EXPECT_EQ(simulateDrivingLog(options).samples.back().x, log.samples.back().x);  // deterministic
  const DrivingStates states = drivingStates(log, "simulated");
  const RollCurvatureSpeedTable table = dataRollCurvatureTable(
      states, defaultRollEdges(), defaultCurvatureEdges(), DataTableOptions{});
  const BinEdges& roll = table.rollEdges();
  const BinEdges& curvature = table.curvatureEdges();
  int avoided_filled = 0, straight_filled = 0;
  for (int i = 0; i < roll.binCount(); ++i) {
    for (int j = 0; j < curvature.binCount(); ++j) {
      const double r_lo = roll.edges()[static_cast<std::size_t>(i)],
                   r_hi = roll.edges()[static_cast<std::size_t>(i) + 1];
      const double k_lo = curvature.edges()[static_cast<std::size_t>(j)],
                   k_hi = curvature.edges()[static_cast<std::size_t>(j) + 1];
      // Entirely inside the avoided region: roll beyond 0.1 on the turn's side, |kappa| > 0.4.
      const bool avoided = (k_lo >= 0.4 && r_lo >= 0.1) || (k_hi <= -0.4 && r_hi <= -0.1);
      if (avoided) avoided_filled += table.vMax()(i, j) > 0.0;
      if (std::abs(curvature.centre(j)) < 0.1 && std::abs(roll.centre(i)) < 0.1) {
        straight_filled += table.vMax()(i, j) > 0.0;
      }
    }
  }
  EXPECT_EQ(avoided_filled, 0);
  EXPECT_EQ(straight_filled, 8);  // 4 roll bins x 2 curvature bins near straight and level
  const PitchSpeedTable pitch = dataPitchTable(states, defaultPitchEdges(), DataTableOptions{});
  EXPECT_GT(pitch.lookup(0.0), 5.0);  // fast on the level
}

TEST(DataTables, DrivingStatesNeedTheirColumns) {
  Trajectory log;
  log.samples.push_back(TrajectorySample::unknown());
  log.has_column[static_cast<std::size_t>(TrajectoryColumn::kX)] = true;
  EXPECT_THAT(errorOf([&] { drivingStates(log, "drive.csv"); }),
              HasSubstr("drive.csv: needs a 'roll' column"));
  log.has_column.fill(true);
  log.has_column[static_cast<std::size_t>(TrajectoryColumn::kCurvature)] = false;
  log.has_column[static_cast<std::size_t>(TrajectoryColumn::kOmega)] = false;
  EXPECT_THAT(errorOf([&] { drivingStates(log, "drive.csv"); }),
              HasSubstr("'curvature' or an 'omega'"));
}

}  // namespace
}  // namespace terratraj::models
