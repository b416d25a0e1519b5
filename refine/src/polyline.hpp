#pragma once
// A trajectory's x, y path as a polyline, and its length (internal to refine/src).

#include <Eigen/Core>
#include <vector>

#include "terratraj/models/trajectory.hpp"

namespace terratraj::refine::detail {

/// The length of the polyline through `points` [m].
inline double polylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

/// The samples' (x, y) [m].
inline std::vector<Eigen::Vector2d> polyline(const models::Trajectory& t) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(t.samples.size());
  for (const models::TrajectorySample& s : t.samples) points.emplace_back(s.x, s.y);
  return points;
}

}  // namespace terratraj::refine::detail
