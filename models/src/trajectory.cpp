#include "terratraj/models/trajectory.hpp"

#include <cmath>
#include <limits>

namespace terratraj::models {
namespace {

constexpr std::array<const char*, kTrajectoryColumnCount> kColumnNames{
    "t", "x", "y", "z", "heading", "roll", "pitch", "v", "omega", "curvature"};

// The samples' members in TrajectoryColumn order.
constexpr std::array<double TrajectorySample::*, kTrajectoryColumnCount> kMembers{
    &TrajectorySample::t,        &TrajectorySample::x,       &TrajectorySample::y,
    &TrajectorySample::z,        &TrajectorySample::heading, &TrajectorySample::roll,
    &TrajectorySample::pitch,    &TrajectorySample::v,       &TrajectorySample::omega,
    &TrajectorySample::curvature};

}  // namespace

const char* trajectoryColumnName(TrajectoryColumn column) {
  return kColumnNames[static_cast<std::size_t>(column)];
}

std::optional<TrajectoryColumn> parseTrajectoryColumn(std::string_view name) {
  for (std::size_t i = 0; i < kColumnNames.size(); ++i) {
    if (name == kColumnNames[i]) return static_cast<TrajectoryColumn>(i);
  }
  return std::nullopt;
}

TrajectorySample TrajectorySample::unknown() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {nan, nan, nan, nan, nan, nan, nan, nan, nan, nan};
}

double TrajectorySample::get(TrajectoryColumn column) const {
  return this->*kMembers[static_cast<std::size_t>(column)];
}

void TrajectorySample::set(TrajectoryColumn column, double value) {
  this->*kMembers[static_cast<std::size_t>(column)] = value;
}

double Trajectory::planarLength() const {
  double length = 0.0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    length += std::hypot(samples[i].x - samples[i - 1].x, samples[i].y - samples[i - 1].y);
  }
  return length;
}

std::string Trajectory::sampleName(std::size_t index) const {
  if (index < source_lines.size()) return "line " + std::to_string(source_lines[index]);
  return "row " + std::to_string(index + 1);
}

}  // namespace terratraj::models
