#pragma once
// Trajectory: a time-sampled vehicle trajectory, the unit that solvers, planners and the CSV
// files of the contract exchange (../shared/spec/interface.md, "Trajectory CSV").

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace terratraj::models {

/// The columns of a trajectory, in the contract's CSV order.
enum class TrajectoryColumn { kT, kX, kY, kZ, kHeading, kRoll, kPitch, kV, kOmega, kCurvature };

/// Number of TrajectoryColumn values.
inline constexpr std::size_t kTrajectoryColumnCount = 10;

/// The CSV header name of a column ("t", "x", ..., "curvature").
const char* trajectoryColumnName(TrajectoryColumn column);
/// The column a CSV header name denotes; std::nullopt if it is not one of the contract's.
std::optional<TrajectoryColumn> parseTrajectoryColumn(std::string_view name);

/// One sample. Units: t [s]; x, y, z [m] (local map frame); heading, roll, pitch [rad];
/// v [m/s]; omega [rad/s]; curvature [1/m]. A value that is not known is NaN.
struct TrajectorySample {
  double t, x, y, z, heading, roll, pitch, v, omega, curvature;

  /// A sample with every value NaN.
  static TrajectorySample unknown();
  /// Access by column.
  double get(TrajectoryColumn column) const;
  void set(TrajectoryColumn column, double value);
};

/// A sequence of samples and which columns hold data (the others are NaN).
struct Trajectory {
  std::vector<TrajectorySample> samples;
  std::array<bool, kTrajectoryColumnCount> has_column{};  ///< indexed by TrajectoryColumn
  std::vector<std::string> ignored_columns;  ///< CSV columns read but not of the contract
  /// The file line of each sample when read from a CSV (the header is line 1); empty otherwise.
  std::vector<std::size_t> source_lines;

  bool has(TrajectoryColumn column) const { return has_column[static_cast<std::size_t>(column)]; }
  /// Sum of the horizontal distances between consecutive samples [m].
  double planarLength() const;
  /// Where sample `index` is, for messages: "line 14" (its file line, when read from a CSV) or
  /// "row 13" (the data row counted from 1).
  std::string sampleName(std::size_t index) const;
};

}  // namespace terratraj::models
