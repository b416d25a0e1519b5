#include "terratraj/models/trajectory_verdict.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace terratraj::models {
namespace {

// writeTrajectoryCsv's rounding (std::setprecision(12) in the default float format).
double rounded(double value) {
  if (!std::isfinite(value)) return value;
  char text[40];
  std::snprintf(text, sizeof(text), "%.12g", value);
  return std::strtod(text, nullptr);
}

bool isMapRule(const std::string& limit) {
  return limit == "lethal" || limit == "no_data" || limit == "off_map" || limit == "attitude";
}

bool isUnusableRule(const std::string& limit) {
  return limit == "empty" || limit == "finite" || limit == "time_order" ||
         limit == "start_position" || limit == "start_speed";
}

bool isGoalRule(const std::string& limit) {
  return limit == "goal_position" || limit == "goal_heading" || limit == "goal_speed";
}

}  // namespace

const char* verdictFailureName(VerdictFailure failure) {
  switch (failure) {
    case VerdictFailure::kNone:
      return "none";
    case VerdictFailure::kUnusable:
      return "unusable";
    case VerdictFailure::kCrossesMap:
      return "crosses_map";
    case VerdictFailure::kBreaksLimits:
      return "breaks_limits";
    case VerdictFailure::kMissesGoal:
      return "misses_goal";
  }
  return "unknown";
}

Trajectory asWritten(const Trajectory& trajectory) {
  Trajectory written = trajectory;
  for (TrajectorySample& sample : written.samples) {
    for (std::size_t c = 0; c < kTrajectoryColumnCount; ++c) {
      const auto column = static_cast<TrajectoryColumn>(c);
      sample.set(column, rounded(sample.get(column)));
    }
  }
  return written;
}

TrajectoryVerdict judgeTrajectory(const Trajectory& trajectory,
                                  const TrajectoryRequirements& requirements) {
  TrajectoryVerdict verdict;
  verdict.check = checkTrajectory(asWritten(trajectory), requirements);
  bool unusable = false, map = false, limits = false, goal = false;
  for (const CheckViolation& v : verdict.check.violations) {
    if (isUnusableRule(v.limit)) {
      unusable = true;
    } else if (isMapRule(v.limit)) {
      map = true;
    } else if (isGoalRule(v.limit)) {
      goal = true;
    } else {
      limits = true;
    }
  }
  verdict.failure = unusable ? VerdictFailure::kUnusable
                    : map    ? VerdictFailure::kCrossesMap
                    : limits ? VerdictFailure::kBreaksLimits
                    : goal   ? VerdictFailure::kMissesGoal
                             : VerdictFailure::kNone;
  verdict.misses_goal = goal;
  if (verdict.passes()) return verdict;
  std::ostringstream reason;
  reason << "the written trajectory fails the independent check: ";
  const std::string summary = verdict.check.summary();
  for (char c : summary) reason << (c == '\n' ? std::string("; ") : std::string(1, c));
  verdict.reason = reason.str();
  return verdict;
}

}  // namespace terratraj::models
