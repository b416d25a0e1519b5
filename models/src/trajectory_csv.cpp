#include "terratraj/models/trajectory_csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  throw InputError(source + ":" + std::to_string(line) + ": " + what);
}

// Where each CSV field goes: a contract column, or nowhere (an ignored extra column).
std::vector<std::optional<TrajectoryColumn>> parseHeader(const std::string& line,
                                                         const std::string& source,
                                                         Trajectory& trajectory) {
  std::vector<std::optional<TrajectoryColumn>> layout;
  for (const std::string& name : splitFields(line)) {
    const std::optional<TrajectoryColumn> column = parseTrajectoryColumn(name);
    if (column) {
      if (trajectory.has(*column)) fail(source, 1, "column '" + name + "' appears twice");
      trajectory.has_column[static_cast<std::size_t>(*column)] = true;
    } else {
      if (name.empty()) fail(source, 1, "empty column name in the header");
      trajectory.ignored_columns.push_back(name);
    }
    layout.push_back(column);
  }
  if (!trajectory.has(TrajectoryColumn::kX) || !trajectory.has(TrajectoryColumn::kY)) {
    fail(source, 1, "the header must name the columns x and y (got '" + trim(line) + "')");
  }
  return layout;
}

// t, x and y must be finite numbers; the other columns may also be "nan" (value not known).
double parseNumber(const std::string& field, const std::string& source, std::size_t line,
                   TrajectoryColumn column) {
  const bool may_be_unknown = column != TrajectoryColumn::kT && column != TrajectoryColumn::kX &&
                              column != TrajectoryColumn::kY;
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);
  const bool parsed = !field.empty() && end == field.c_str() + field.size() && errno != ERANGE;
  if (parsed && (std::isfinite(value) || (may_be_unknown && std::isnan(value)))) return value;
  fail(source, line,
       std::string("column ") + trajectoryColumnName(column) + ": '" + field +
           (may_be_unknown ? "' is neither a finite number nor nan" : "' is not a finite number"));
}

}  // namespace

Trajectory readTrajectoryCsv(std::istream& in, const std::string& source) {
  Trajectory trajectory;
  std::string line;
  if (!std::getline(in, line) || trim(line).empty()) fail(source, 1, "no header line");
  const std::vector<std::optional<TrajectoryColumn>> layout = parseHeader(line, source, trajectory);
  std::size_t line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (trim(line).empty()) continue;
    const std::vector<std::string> fields = splitFields(line);
    if (fields.size() != layout.size()) {
      fail(source, line_number,
           "expected " + std::to_string(layout.size()) + " fields, got " +
               std::to_string(fields.size()));
    }
    TrajectorySample sample = TrajectorySample::unknown();
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (!layout[i]) continue;
      sample.set(*layout[i], parseNumber(fields[i], source, line_number, *layout[i]));
    }
    if (trajectory.has(TrajectoryColumn::kT) && !trajectory.samples.empty() &&
        !(sample.t > trajectory.samples.back().t)) {
      fail(source, line_number, "t must increase strictly from row to row");
    }
    trajectory.samples.push_back(sample);
    trajectory.source_lines.push_back(line_number);
  }
  if (trajectory.samples.empty()) fail(source, line_number, "no data rows after the header");
  return trajectory;
}

Trajectory readTrajectoryCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be opened for reading");
  return readTrajectoryCsv(in, path.string());
}

std::vector<double> platformPitchColumn(const Trajectory& trajectory,
                                        const SegwayPitchResponse& platform) {
  const std::vector<TrajectorySample>& samples = trajectory.samples;
  std::vector<double> column(samples.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    double acceleration = 0.0;
    if (samples.size() > 1) {
      const std::size_t a = i + 1 < samples.size() ? i : i - 1;
      acceleration = (samples[a + 1].v - samples[a].v) / (samples[a + 1].t - samples[a].t);
    }
    if (std::isfinite(acceleration) && std::isfinite(samples[i].pitch)) {
      column[i] = platform.pitch(acceleration, samples[i].pitch);
    }
  }
  return column;
}

void writeTrajectoryCsv(const Trajectory& trajectory, std::ostream& out,
                        const SegwayPitchResponse* platform) {
  const std::vector<double> platform_pitch =
      platform != nullptr ? platformPitchColumn(trajectory, *platform) : std::vector<double>{};
  const auto write = [&out](double value) {
    if (std::isnan(value)) {
      out << "nan";
    } else {
      out << value;
    }
  };
  for (std::size_t i = 0; i < kTrajectoryColumnCount; ++i) {
    out << (i ? "," : "") << trajectoryColumnName(static_cast<TrajectoryColumn>(i));
  }
  if (platform != nullptr) out << ",platform_pitch";
  out << '\n' << std::setprecision(12);
  for (std::size_t row = 0; row < trajectory.samples.size(); ++row) {
    const TrajectorySample& sample = trajectory.samples[row];
    for (std::size_t i = 0; i < kTrajectoryColumnCount; ++i) {
      out << (i ? "," : "");
      write(sample.get(static_cast<TrajectoryColumn>(i)));
    }
    if (platform != nullptr) {
      out << ',';
      write(platform_pitch[row]);
    }
    out << '\n';
  }
}

void writeTrajectoryCsv(const Trajectory& trajectory, const std::filesystem::path& path,
                        const SegwayPitchResponse* platform) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string() + ": cannot be opened for writing");
  writeTrajectoryCsv(trajectory, out, platform);
  out.flush();
  if (!out) throw InputError(path.string() + ": write error");
}

}  // namespace terratraj::models
