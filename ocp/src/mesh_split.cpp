#include "terratraj/ocp/mesh_split.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {

double groundLimitExcess(const BoundaryValueProblem& problem, const models::Attitude& attitude,
                         double v, double curvature) {
  const models::VehicleLimits& l = problem.limits;
  return std::max({std::abs(attitude.pitch) / l.pitch_max - 1.0,
                   std::abs(attitude.roll) / l.roll_max - 1.0,
                   (v - problem.tables.speedCap(attitude, curvature, l.v_max)) / l.v_max});
}

std::vector<double> intervalLimitExcess(const models::Trajectory& trajectory,
                                        const std::vector<double>& mesh_times,
                                        const BoundaryValueProblem& problem) {
  const int intervals = static_cast<int>(mesh_times.size()) - 1;
  std::vector<double> excess(static_cast<std::size_t>(std::max(intervals, 0)), 0.0);
  if (intervals < 1 || trajectory.samples.empty()) return excess;
  const models::VehicleLimits& l = problem.limits;
  const std::vector<models::TrajectorySample>& s = trajectory.samples;
  const double t0 = s.front().t;
  int k = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double t = s[i].t - t0;
    while (k + 1 < intervals && t > mesh_times[static_cast<std::size_t>(k) + 1]) ++k;
    const models::Attitude attitude{s[i].z, s[i].roll, s[i].pitch};
    const double curvature = std::isfinite(s[i].curvature) ? s[i].curvature : 0.0;
    double e = groundLimitExcess(problem, attitude, s[i].v, curvature);
    if (i + 1 < s.size() && s[i + 1].t > s[i].t) {
      const models::Attitude next{s[i + 1].z, s[i + 1].roll, s[i + 1].pitch};
      const double cap = std::max(problem.tables.accelerationCap(attitude, l.a_max),
                                  problem.tables.accelerationCap(next, l.a_max));
      const double acceleration = std::abs(s[i + 1].v - s[i].v) / (s[i + 1].t - s[i].t);
      e = std::max(e, (acceleration - cap) / l.a_max);
    }
    double& slot = excess[static_cast<std::size_t>(k)];
    if (std::isfinite(e)) slot = std::max(slot, e);
  }
  return excess;
}

std::vector<double> splitIntervals(const std::vector<double>& mesh, const std::vector<bool>& split,
                                   int max_intervals) {
  std::vector<double> out;
  if (mesh.empty()) return out;
  out.reserve(2 * mesh.size());
  int count = static_cast<int>(mesh.size()) - 1;
  for (std::size_t k = 0; k + 1 < mesh.size(); ++k) {
    out.push_back(mesh[k]);
    if (k < split.size() && split[k] && count < max_intervals) {
      out.push_back(0.5 * (mesh[k] + mesh[k + 1]));
      ++count;
    }
  }
  out.push_back(mesh.back());
  return out;
}

}  // namespace terratraj::ocp
