#include "terratraj/ocp/interval_bound_rows.hpp"

#include <algorithm>
#include <cmath>

#include "terratraj/ocp/transcription_nlp.hpp"

namespace terratraj::ocp {
namespace {

// The variables of a point the rows use.
constexpr int kV = 3, kOmega = 4, kVDot = 5, kOmegaDot = 6;

bool usable(double limit) { return std::isfinite(limit) && limit > 0.0; }

}  // namespace

IntervalBoundRows::IntervalBoundRows(TranscriptionScheme scheme, const std::vector<double>& mesh,
                                     const models::VehicleLimits& limits, double final_time) {
  if (scheme == TranscriptionScheme::kMultipleShooting || mesh.size() < 2 || !(final_time > 0.0) ||
      !std::isfinite(final_time)) {
    return;
  }
  // (c_v, c_omega, bound, name) of each limit.
  struct Limit {
    double c_v, c_omega, bound;
    const char* name;
  };
  std::vector<Limit> linear;
  if (usable(limits.v_max)) linear.push_back({1.0, 0.0, limits.v_max, "v_max_between_points"});
  linear.push_back({-1.0, 0.0, 0.0, "v_min_between_points"});
  if (usable(limits.omega_max)) {
    linear.push_back({0.0, 1.0, limits.omega_max, "omega_max_between_points"});
    linear.push_back({0.0, -1.0, limits.omega_max, "omega_max_between_points"});
  }
  if (usable(limits.kappa_max)) {
    linear.push_back({-limits.kappa_max, 1.0, 0.0, "kappa_max_between_points"});
    linear.push_back({-limits.kappa_max, -1.0, 0.0, "kappa_max_between_points"});
  }
  const bool hs = scheme == TranscriptionScheme::kHermiteSimpson;
  const int intervals = static_cast<int>(mesh.size()) - 1;
  rows_.reserve(static_cast<std::size_t>(intervals) * (hs ? 2 : 1) * linear.size());
  for (int k = 0; k < intervals; ++k) {
    const double h =
        final_time * (mesh[static_cast<std::size_t>(k) + 1] - mesh[static_cast<std::size_t>(k)]);
    for (const Limit& l : linear) {
      if (hs) {
        rows_.push_back({2 * k, h / 3.0, l.c_v, l.c_omega, l.bound, l.name});
        rows_.push_back({2 * k + 2, -h / 3.0, l.c_v, l.c_omega, l.bound, l.name});
      } else {
        rows_.push_back({k, h / 2.0, l.c_v, l.c_omega, l.bound, l.name});
      }
    }
  }
}

void IntervalBoundRows::appendStructure(int first_row, std::vector<int>& rows,
                                        std::vector<int>& cols) const {
  int r = first_row;
  for (const Row& row : rows_) {
    for (int j : {kV, kOmega, kVDot, kOmegaDot}) {
      rows.push_back(r);
      cols.push_back(kPointSize * row.point + j);
    }
    ++r;
  }
}

void IntervalBoundRows::evaluate(const Eigen::Ref<const Eigen::VectorXd>& x, double* g) const {
  for (const Row& row : rows_) {
    const int base = kPointSize * row.point;
    *g++ = row.c_v * (x(base + kV) + row.step * x(base + kVDot)) +
           row.c_omega * (x(base + kOmega) + row.step * x(base + kOmegaDot)) - row.bound;
  }
}

void IntervalBoundRows::jacobian(double* jacobian) const {
  for (const Row& row : rows_) {
    *jacobian++ = row.c_v;
    *jacobian++ = row.c_omega;
    *jacobian++ = row.c_v * row.step;
    *jacobian++ = row.c_omega * row.step;
  }
}

double intervalBoundsFinalTime(const BoundaryValueProblem& problem, double guess_final_time) {
  const models::VehicleLimits& l = problem.limits;
  const double distance =
      std::hypot(problem.goal.x - problem.start.x, problem.goal.y - problem.start.y);
  const double v = std::max(l.v_max, 1e-3);
  const double straight = distance / v + v / std::max(l.a_max, 1e-3);
  return std::min(guess_final_time, 2.0 * straight);
}

}  // namespace terratraj::ocp
