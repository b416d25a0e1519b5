#include "terratraj/search/continuous_curvature_steering.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::search {

TurnShape ContinuousCurvatureSteering::turnShape(double v_start, double kappa_start,
                                                 double v_preferred) const {
  const double v_max = limits_.v_max;
  double upper = v_max;
  if (kappa_start != 0.0) upper = std::min(upper, limits_.omega_max / std::abs(kappa_start));
  const double lower = std::min(upper, std::max(v_start, kMinTurnSpeedFraction * v_max));
  TurnShape turn;
  turn.turn_speed = std::clamp(v_preferred, lower, upper);
  turn.sharpness = limits_.sigma_max / turn.turn_speed;
  turn.turn_curvature = std::min(limits_.kappa_max, limits_.omega_max / turn.turn_speed);
  return turn;
}

double ContinuousCurvatureSteering::straighten(double kappa, double ds, const TurnShape& turn) {
  const double magnitude = std::max(0.0, std::abs(kappa) - turn.sharpness * ds);
  return kappa >= 0.0 ? magnitude : -magnitude;
}

double ContinuousCurvatureSteering::rampDownHeading(double kappa, double sharpness) {
  return kappa * std::abs(kappa) / (2.0 * sharpness);
}

double ContinuousCurvatureSteering::nextCurvature(double kappa, double heading_error, double ds,
                                                  const TurnShape& turn) const {
  // Mirror a right turn onto a left one: e >= 0, curvature k in the turn's direction.
  const double sign = heading_error >= 0.0 ? 1.0 : -1.0;
  const double e = std::abs(heading_error);
  const double k = sign * kappa;
  const double c = turn.sharpness;
  const double step = c * ds;
  // On the line: a heading error this small with a curvature one step can remove is taken as
  // zero (the discrete law would otherwise zig-zag around the line).
  if (e <= kLineCaptureHeading && std::abs(k) <= step) return 0.0;
  // Largest k1 >= 0 with k1^2 / (2c) + (k + k1) ds / 2 <= e: the heading of this step plus the
  // anti-clothoid after it does not overshoot the remaining error.
  double k1 = k - step;  // overshooting already: brake the turn as fast as allowed
  const double remaining = e - 0.5 * k * ds;
  if (remaining >= 0.0) {
    const double root = c * (-0.5 * ds + std::sqrt(0.25 * ds * ds + 2.0 * remaining / c));
    k1 = std::clamp(root, k - step, k + step);
  }
  // Stay within the turn curvature, or move toward it when starting outside.
  const double kt = turn.turn_curvature;
  k1 = std::min(k1, std::max(kt, k - step));
  k1 = std::max(k1, std::min(-kt, k + step));
  return sign * k1;
}

}  // namespace terratraj::search
