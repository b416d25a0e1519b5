#include "candidate_completion.hpp"

#include <algorithm>
#include <cmath>

#include "format_number.hpp"

namespace terratraj::refine::detail {

using models::TrajectoryColumn;

std::string formatPoint(double x, double y) {
  return "(" + formatNumber(x) + ", " + formatNumber(y) + ")";
}

std::optional<std::string> candidateError(const models::Trajectory& candidate,
                                          const terrain::GridGeometry& geometry) {
  if (!candidate.has(TrajectoryColumn::kX) || !candidate.has(TrajectoryColumn::kY)) {
    return std::string("the candidate has no x and y columns");
  }
  if (candidate.samples.size() < 2) {
    return "the candidate is a single point (" + std::to_string(candidate.samples.size()) +
           " sample" + (candidate.samples.size() == 1 ? "" : "s") + "): a path needs two";
  }
  bool distinct = false;
  const models::TrajectorySample& first = candidate.samples.front();
  for (std::size_t i = 0; i < candidate.samples.size(); ++i) {
    const models::TrajectorySample& s = candidate.samples[i];
    if (!std::isfinite(s.x) || !std::isfinite(s.y)) {
      return candidate.sampleName(i) + ": x, y is not a finite number";
    }
    if (!geometry.contains({s.x, s.y})) {
      return candidate.sampleName(i) + " at " + formatPoint(s.x, s.y) + " leaves the map (0..." +
             formatNumber(geometry.width()) + " x 0..." + formatNumber(geometry.height()) +
             " m, local frame)";
    }
    if (std::hypot(s.x - first.x, s.y - first.y) > 1e-6) distinct = true;
  }
  if (!distinct) return std::string("the candidate is a single point: all its samples coincide");
  return std::nullopt;
}

bool hasTiming(const models::Trajectory& t) {
  if (!t.has(TrajectoryColumn::kT) || !t.has(TrajectoryColumn::kV) ||
      !t.has(TrajectoryColumn::kHeading)) {
    return false;
  }
  return std::all_of(t.samples.begin(), t.samples.end(), [](const models::TrajectorySample& s) {
    return std::isfinite(s.t) && std::isfinite(s.v) && std::isfinite(s.heading);
  });
}

bool fillAttitude(const models::TerrainFollowingModel& vehicle, models::Trajectory& trajectory,
                  std::string& why) {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    models::TrajectorySample& s = trajectory.samples[i];
    const models::AttitudeStatus status = vehicle.compute({s.x, s.y, s.heading}, workspace, result);
    if (status != models::AttitudeStatus::kOk) {
      why = trajectory.sampleName(i) + " at " + formatPoint(s.x, s.y) +
            ": the vehicle cannot rest there (" + models::attitudeStatusName(status) + ")";
      return false;
    }
    s.z = result.attitude.z;
    s.roll = result.attitude.roll;
    s.pitch = result.attitude.pitch;
  }
  for (TrajectoryColumn c :
       {TrajectoryColumn::kZ, TrajectoryColumn::kRoll, TrajectoryColumn::kPitch}) {
    trajectory.has_column[static_cast<std::size_t>(c)] = true;
  }
  return true;
}

models::Trajectory completeCandidate(const models::Trajectory& candidate,
                                     const ocp::TranscriptionGuess& guess) {
  models::Trajectory full;
  if (hasTiming(candidate)) {
    full = candidate;
    // Fill what is missing from the guess built on the same samples.
    for (std::size_t i = 0; i < full.samples.size() && i < guess.points.size(); ++i) {
      models::TrajectorySample& s = full.samples[i];
      const ocp::PointVector& w = guess.points[i];
      if (!full.has(TrajectoryColumn::kOmega) || !std::isfinite(s.omega)) s.omega = w(4);
      if (!full.has(TrajectoryColumn::kCurvature) || !std::isfinite(s.curvature)) {
        s.curvature = s.v > 1e-9 ? s.omega / s.v : 0.0;
      }
    }
  } else {
    full.samples.reserve(guess.points.size());
    for (std::size_t i = 0; i < guess.points.size(); ++i) {
      const ocp::PointVector& w = guess.points[i];
      models::TrajectorySample s = models::TrajectorySample::unknown();
      s.t = guess.t[i];
      s.x = w(0);
      s.y = w(1);
      s.heading = w(2);
      s.v = w(3);
      s.omega = w(4);
      s.curvature = w(3) > 1e-9 ? w(4) / w(3) : 0.0;
      full.samples.push_back(s);
    }
  }
  full.ignored_columns.clear();
  for (TrajectoryColumn c : {TrajectoryColumn::kT, TrajectoryColumn::kX, TrajectoryColumn::kY,
                             TrajectoryColumn::kHeading, TrajectoryColumn::kV,
                             TrajectoryColumn::kOmega, TrajectoryColumn::kCurvature}) {
    full.has_column[static_cast<std::size_t>(c)] = true;
  }
  return full;
}

}  // namespace terratraj::refine::detail
