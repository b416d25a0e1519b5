#include "terratraj/models/trajectory_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

using ::testing::HasSubstr;

std::string readError(const std::string& text) {
  std::istringstream in(text);
  try {
    readTrajectoryCsv(in, "traj.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

Trajectory read(const std::string& text) {
  std::istringstream in(text);
  return readTrajectoryCsv(in, "traj.csv");
}

TEST(TrajectoryCsv, WritesTheContractHeaderAndReadsItBack) {
  Trajectory trajectory;
  for (int i = 0; i < 5; ++i) {
    trajectory.samples.push_back({0.1 * i, 1.0 + i, 2.0, 0.5, 0.1, -0.02, 0.03, 1.0, 0.2, 0.2});
  }
  trajectory.samples[2].roll = std::nan("");
  std::ostringstream out;
  writeTrajectoryCsv(trajectory, out);
  EXPECT_EQ(out.str().substr(0, out.str().find('\n')),
            "t,x,y,z,heading,roll,pitch,v,omega,curvature");
  const Trajectory back = read(out.str());
  ASSERT_EQ(back.samples.size(), 5u);
  for (std::size_t c = 0; c < kTrajectoryColumnCount; ++c) EXPECT_TRUE(back.has_column[c]);
  EXPECT_DOUBLE_EQ(back.samples[4].x, 5.0);
  EXPECT_DOUBLE_EQ(back.samples[3].t, 0.3);
  EXPECT_TRUE(std::isnan(back.samples[2].roll));
  EXPECT_DOUBLE_EQ(back.samples[1].curvature, 0.2);
}

// The Segway RMP's CSV (contract, Additions): platform_pitch after curvature, at each row the
// pitch response at the acceleration of the segment after it (the last row: before it) and the
// row's slope; the file reads back with the column skipped.
TEST(TrajectoryCsv, TheSegwaysCsvCarriesThePlatformPitch) {
  const SegwayPitchResponse response = defaultSegwayLookups().pitch_response;
  Trajectory trajectory;
  const double v[] = {0.0, 0.5, 0.75, 0.75};  // accelerating at 1, 0.5, 0 m/s^2 over 0.5 s each
  const double slope[] = {0.1, 0.2, -0.1, 0.0};
  for (int i = 0; i < 4; ++i) {
    trajectory.samples.push_back({0.5 * i, 1.0 + i, 2.0, 0.5, 0.0, 0.0, slope[i], v[i], 0.0, 0.0});
  }
  trajectory.samples[1].pitch = std::nan("");
  std::ostringstream out;
  writeTrajectoryCsv(trajectory, out, &response);
  EXPECT_EQ(out.str().substr(0, out.str().find('\n')),
            "t,x,y,z,heading,roll,pitch,v,omega,curvature,platform_pitch");
  const Trajectory back = read(out.str());
  EXPECT_EQ(back.ignored_columns, std::vector<std::string>{"platform_pitch"});
  const std::vector<double> column = platformPitchColumn(trajectory, response);
  ASSERT_EQ(column.size(), 4u);
  EXPECT_NEAR(column[0], response.pitch(1.0, 0.1), 1e-12);
  EXPECT_TRUE(std::isnan(column[1]));  // its slope is not known
  EXPECT_NEAR(column[2], response.pitch(0.0, -0.1), 1e-12);
  EXPECT_NEAR(column[3], response.pitch(0.0, 0.0), 1e-12);
  // Accelerating uphill tips the platform further than holding speed on the flat.
  EXPECT_GT(std::abs(column[0]), std::abs(column[3]) + 0.05);
  std::istringstream rows(out.str());
  std::string line;
  std::getline(rows, line);
  std::getline(rows, line);
  EXPECT_NEAR(std::stod(line.substr(line.rfind(',') + 1)), column[0], 1e-9);
}

TEST(TrajectoryCsv, ReadsGeometricPathsInAnyColumnOrder) {
  const Trajectory path = read("y,x\n0,0\n0,1\n1,1\n");
  ASSERT_EQ(path.samples.size(), 3u);
  EXPECT_TRUE(path.has(TrajectoryColumn::kX));
  EXPECT_FALSE(path.has(TrajectoryColumn::kHeading));
  EXPECT_TRUE(std::isnan(path.samples[0].heading));
  EXPECT_DOUBLE_EQ(path.samples[2].y, 1.0);
  EXPECT_DOUBLE_EQ(path.planarLength(), 2.0);
  const Trajectory with_extra = read("x,y,heading,speed_cmd\r\n0,0,0,1\r\n1,0,0,1\r\n");
  EXPECT_EQ(with_extra.ignored_columns, std::vector<std::string>{"speed_cmd"});
  EXPECT_TRUE(with_extra.has(TrajectoryColumn::kHeading));
}

TEST(TrajectoryCsv, BadInputNamesTheLineAndColumn) {
  EXPECT_THAT(readError(""), HasSubstr("traj.csv:1: no header"));
  EXPECT_THAT(readError("t,x\n0,1\n"), HasSubstr("must name the columns x and y"));
  EXPECT_THAT(readError("x,y,x\n0,1,2\n"), HasSubstr("column 'x' appears twice"));
  EXPECT_THAT(readError("x,y\n0,1\n0,1,2\n"), HasSubstr("traj.csv:3: expected 2 fields, got 3"));
  EXPECT_THAT(readError("x,y\n0,abc\n"),
              HasSubstr("traj.csv:2: column y: 'abc' is not a finite number"));
  EXPECT_THAT(readError("x,y\nnan,1\n"), HasSubstr("column x: 'nan' is not a finite number"));
  EXPECT_THAT(readError("x,y,v\n0,1,inf\n"), HasSubstr("column v: 'inf'"));
  EXPECT_THAT(readError("x,y\n0,\n"), HasSubstr("column y: ''"));
  EXPECT_THAT(readError("x,y\n"), HasSubstr("no data rows"));
  EXPECT_THAT(readError("t,x,y\n0,0,0\n0,1,1\n"), HasSubstr("traj.csv:3: t must increase"));
  EXPECT_THAT(readError("x,,y\n0,1,2\n"), HasSubstr("empty column name"));
}

TEST(TrajectoryCsv, FilesThatCannotBeOpened) {
  try {
    readTrajectoryCsv(std::filesystem::path("/nonexistent/traj.csv"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/traj.csv: cannot be opened"));
  }
  EXPECT_THROW(writeTrajectoryCsv(Trajectory{}, std::filesystem::path("/nonexistent/out.csv")),
               InputError);
}

}  // namespace
}  // namespace terratraj::models
