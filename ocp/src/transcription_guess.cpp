#include "terratraj/ocp/transcription_guess.hpp"

#include <algorithm>
#include <cmath>

#include "terratraj/ocp/mesh_split.hpp"

namespace terratraj::ocp {
namespace {

using models::TrajectoryColumn;

// v' and omega' by differences of v and omega over the samples.
void differentiateControls(TranscriptionGuess& guess) {
  const std::size_t n = guess.t.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, n - 1);
    const double dt = guess.t[b] - guess.t[a];
    if (dt <= 0.0) continue;
    guess.points[i](5) = (guess.points[b](3) - guess.points[a](3)) / dt;
    guess.points[i](6) = (guess.points[b](4) - guess.points[a](4)) / dt;
  }
}

// The speed tables' bounds along the path (SpeedTables::speedCap at the vehicle's attitude on
// each sample, with the same 0.8 margin as the limits), and the Segway's acceleration bound by
// slope. Where a table forbids driving (cap 0: the Segway beyond its drivable slope), the guess
// keeps a tenth of the limits rather than stopping mid-path: the optimiser has to leave such a
// path anyway, and a guess at rest there would leave it no direction.
void capByTables(const std::vector<Eigen::Vector2d>& xy, const std::vector<double>& heading,
                 const std::vector<double>& curvature, const BoundaryValueProblem& problem,
                 const models::TerrainFollowingModel& vehicle, std::vector<double>& v,
                 std::vector<double>& accel) {
  const SpeedTables& tables = problem.tables;
  if (tables.pitch == nullptr && tables.roll_curvature == nullptr && tables.segway == nullptr) {
    return;
  }
  const models::VehicleLimits& l = problem.limits;
  models::AttitudeWorkspace workspace;
  models::AttitudeResult placed;
  for (std::size_t i = 0; i < xy.size(); ++i) {
    if (vehicle.compute({xy[i].x(), xy[i].y(), heading[i]}, workspace, placed) !=
        models::AttitudeStatus::kOk) {
      continue;
    }
    const double cap = tables.speedCap(placed.attitude, curvature[i], l.v_max);
    v[i] = std::min(v[i], std::max(0.8 * cap, 0.1 * l.v_max));
    accel[i] = std::min(
        accel[i], std::max(0.8 * tables.accelerationCap(placed.attitude, l.a_max), 0.1 * l.a_max));
  }
}

}  // namespace

PointVector TranscriptionGuess::at(double time) const {
  if (t.size() == 1 || time <= t.front()) return points.front();
  if (time >= t.back()) return points.back();
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  const double f = (time - t[i - 1]) / (t[i] - t[i - 1]);
  return (1.0 - f) * points[i - 1] + f * points[i];
}

double guessLimitExcess(const TranscriptionGuess& guess, const BoundaryValueProblem& problem,
                        const models::TerrainFollowingModel& vehicle, int samples) {
  if (guess.t.empty() || samples < 2) return 0.0;
  models::AttitudeWorkspace workspace;
  models::AttitudeResult placed;
  double excess = 0.0;
  for (int i = 0; i < samples; ++i) {
    const PointVector w = guess.at(guess.finalTime() * i / (samples - 1));
    if (vehicle.compute({w(0), w(1), w(2)}, workspace, placed) != models::AttitudeStatus::kOk) {
      excess = std::max(excess, 1.0);
      continue;
    }
    const double curvature = std::abs(w(3)) > 1e-9 ? w(4) / w(3) : 0.0;
    excess = std::max(excess, groundLimitExcess(problem, placed.attitude, w(3), curvature));
  }
  return excess;
}

Expected<TranscriptionGuess> guessFromTrajectory(const models::Trajectory& trajectory) {
  for (TrajectoryColumn c : {TrajectoryColumn::kT, TrajectoryColumn::kX, TrajectoryColumn::kY,
                             TrajectoryColumn::kHeading, TrajectoryColumn::kV}) {
    if (!trajectory.has(c)) {
      return unexpected(std::string("the trajectory has no '") + models::trajectoryColumnName(c) +
                        "' column");
    }
  }
  if (trajectory.samples.size() < 2) {
    return unexpected("the trajectory has fewer than two samples");
  }
  TranscriptionGuess guess;
  const double t0 = trajectory.samples.front().t;
  double heading_offset = 0.0, previous_heading = 0.0;
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    const models::TrajectorySample& s = trajectory.samples[i];
    const double t = s.t - t0;
    if (!std::isfinite(t) || !std::isfinite(s.x) || !std::isfinite(s.y) ||
        !std::isfinite(s.heading) || !std::isfinite(s.v) || (i > 0 && !(t > guess.t.back()))) {
      return unexpected("sample " + std::to_string(i) +
                        " of the trajectory is not finite or its time does not increase");
    }
    // Unwrapped heading: continuous across +-pi.
    if (i > 0)
      heading_offset += wrapAngle(s.heading - previous_heading) - (s.heading - previous_heading);
    previous_heading = s.heading;
    PointVector w = PointVector::Zero();
    w << s.x, s.y, s.heading + heading_offset, s.v, 0.0, 0.0, 0.0;
    if (trajectory.has(TrajectoryColumn::kOmega) && std::isfinite(s.omega)) {
      w(4) = s.omega;
    } else if (trajectory.has(TrajectoryColumn::kCurvature) && std::isfinite(s.curvature)) {
      w(4) = s.curvature * s.v;
    }
    guess.t.push_back(t);
    guess.points.push_back(w);
  }
  if (!trajectory.has(TrajectoryColumn::kOmega) && !trajectory.has(TrajectoryColumn::kCurvature)) {
    const std::size_t n = guess.t.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, n - 1);
      guess.points[i](4) = (guess.points[b](2) - guess.points[a](2)) / (guess.t[b] - guess.t[a]);
    }
  }
  differentiateControls(guess);
  return guess;
}

Expected<TranscriptionGuess> guessFromPath(const std::vector<Eigen::Vector2d>& path,
                                           const BoundaryValueProblem& problem, double spacing,
                                           const models::TerrainFollowingModel* vehicle) {
  // Distinct, finite points and their arc length.
  std::vector<Eigen::Vector2d> points;
  std::vector<double> arc;
  for (const Eigen::Vector2d& p : path) {
    if (!p.allFinite()) {
      return unexpected("the path has a non-finite point");
    }
    if (!points.empty() && (p - points.back()).norm() < 1e-9) continue;
    arc.push_back(points.empty() ? 0.0 : arc.back() + (p - points.back()).norm());
    points.push_back(p);
  }
  if (points.size() < 2 || !(spacing > 0.0)) {
    return unexpected("the path has fewer than two distinct points");
  }
  const double length = arc.back();
  const int segments = std::max(2, static_cast<int>(std::ceil(length / spacing)));
  const std::size_t n = static_cast<std::size_t>(segments) + 1;
  std::vector<Eigen::Vector2d> xy(n);
  std::size_t j = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = length * static_cast<double>(i) / segments;
    while (j + 1 < arc.size() && arc[j] < s) ++j;
    const double f = std::clamp((s - arc[j - 1]) / (arc[j] - arc[j - 1]), 0.0, 1.0);
    xy[i] = (1.0 - f) * points[j - 1] + f * points[j];
  }
  const double ds = length / segments;
  // Heading from the tangent, unwrapped; the problem's headings at the ends.
  std::vector<double> heading(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = std::min(i + 1, n - 1);
    const Eigen::Vector2d d = xy[b] - xy[a];
    heading[i] = std::atan2(d.y(), d.x());
    if (i > 0) heading[i] = heading[i - 1] + wrapAngle(heading[i] - heading[i - 1]);
  }
  heading.front() = heading[1] + wrapAngle(problem.start.heading - heading[1]);
  heading.back() = heading[n - 2] + wrapAngle(problem.goal.heading - heading[n - 2]);
  std::vector<double> curvature(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i)
    curvature[i] = (heading[i + 1] - heading[i - 1]) / (2.0 * ds);
  // Speed limits, then a forward-backward pass under a_max.
  const models::VehicleLimits& l = problem.limits;
  const double cruise = 0.8 * l.v_max;  // keep a margin for the optimiser
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    v[i] = cruise;
    const double k = std::abs(curvature[i]);
    if (k > 1e-9) v[i] = std::min(v[i], 0.8 * l.omega_max / k);
  }
  const double a = 0.8 * l.a_max;
  std::vector<double> accel(n, a);
  if (vehicle != nullptr) capByTables(xy, heading, curvature, problem, *vehicle, v, accel);
  v.front() = std::clamp(problem.start.v, 0.0, l.v_max);
  v.back() = std::clamp(problem.goal.v, 0.0, l.v_max);
  for (std::size_t i = 1; i < n; ++i) {
    const double step = std::min(accel[i - 1], accel[i]);
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2.0 * step * ds));
  }
  for (std::size_t i = n - 1; i-- > 0;) {
    const double step = std::min(accel[i], accel[i + 1]);
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * step * ds));
  }
  TranscriptionGuess guess;
  double t = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) {
      const double mean = 0.5 * (v[i] + v[i - 1]);
      t += mean > 1e-6 ? ds / mean : std::sqrt(2.0 * ds / a);
    }
    PointVector w = PointVector::Zero();
    w << xy[i].x(), xy[i].y(), heading[i], v[i], v[i] * curvature[i], 0.0, 0.0;
    guess.t.push_back(t);
    guess.points.push_back(w);
  }
  guess.points.front()(4) = problem.start.omega;
  guess.points.back()(4) = problem.goal.omega;
  differentiateControls(guess);
  return guess;
}

Expected<TranscriptionGuess> guessFromCandidate(const models::Trajectory& candidate,
                                                const BoundaryValueProblem& problem) {
  if (candidate.has(TrajectoryColumn::kT) && candidate.has(TrajectoryColumn::kV) &&
      candidate.has(TrajectoryColumn::kHeading)) {
    return guessFromTrajectory(candidate);
  }
  if (!candidate.has(TrajectoryColumn::kX) || !candidate.has(TrajectoryColumn::kY)) {
    return unexpected("the candidate has no x, y columns");
  }
  std::vector<Eigen::Vector2d> path;
  path.reserve(candidate.samples.size());
  for (const models::TrajectorySample& s : candidate.samples) path.emplace_back(s.x, s.y);
  return guessFromPath(path, problem, 0.25);
}

}  // namespace terratraj::ocp
