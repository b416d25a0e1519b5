#pragma once
// Length of the shortest Dubins path (Dubins 1957; the six words of Shkel & Lumelsky 2001),
// the reference of the curvature-bounded transcription test.

#include <algorithm>
#include <cmath>
#include <limits>

namespace terratraj::ocp::testing {

/// Shortest path [m] from (x0, y0, h0) to (x1, y1, h1) with curvature at most 1 / radius.
inline double dubinsLength(double x0, double y0, double h0, double x1, double y1, double h1,
                           double radius) {
  constexpr double kTwoPi = 6.28318530717958647692;
  // Angle in [0, 2 pi), with rounding just below 2 pi taken as 0 (a zero-length arc).
  const auto mod = [&](double a) {
    const double r = a - kTwoPi * std::floor(a / kTwoPi);
    return r > kTwoPi - 1e-9 ? 0.0 : r;
  };
  const double dx = (x1 - x0) / radius, dy = (y1 - y0) / radius;
  const double d = std::hypot(dx, dy);
  const double theta = mod(std::atan2(dy, dx));
  const double a = mod(h0 - theta), b = mod(h1 - theta);
  const double sa = std::sin(a), sb = std::sin(b), ca = std::cos(a), cb = std::cos(b);
  const double cab = std::cos(a - b);
  double best = std::numeric_limits<double>::infinity();
  // LSL
  double p2 = 2 + d * d - 2 * cab + 2 * d * (sa - sb);
  if (p2 >= -1e-10) {
    p2 = std::max(p2, 0.0);
    const double tmp = std::atan2(cb - ca, d + sa - sb);
    best = std::min(best, mod(-a + tmp) + std::sqrt(p2) + mod(b - tmp));
  }
  // RSR
  p2 = 2 + d * d - 2 * cab + 2 * d * (sb - sa);
  if (p2 >= -1e-10) {
    p2 = std::max(p2, 0.0);
    const double tmp = std::atan2(ca - cb, d - sa + sb);
    best = std::min(best, mod(a - tmp) + std::sqrt(p2) + mod(-b + tmp));
  }
  // LSR
  p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb);
  if (p2 >= -1e-10) {
    p2 = std::max(p2, 0.0);
    const double p = std::sqrt(p2);
    const double tmp = std::atan2(-ca - cb, d + sa + sb) - std::atan2(-2.0, p);
    best = std::min(best, mod(-a + tmp) + p + mod(-mod(b) + tmp));
  }
  // RSL
  p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb);
  if (p2 >= -1e-10) {
    p2 = std::max(p2, 0.0);
    const double p = std::sqrt(p2);
    const double tmp = std::atan2(ca + cb, d - sa - sb) - std::atan2(2.0, p);
    best = std::min(best, mod(a - tmp) + p + mod(b - tmp));
  }
  // RLR
  double tmp = (6 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8;
  if (std::abs(tmp) <= 1) {
    const double p = mod(kTwoPi - std::acos(tmp));
    const double t = mod(a - std::atan2(ca - cb, d - sa + sb) + p / 2);
    best = std::min(best, t + p + mod(a - b - t + p));
  }
  // LRL
  tmp = (6 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8;
  if (std::abs(tmp) <= 1) {
    const double p = mod(kTwoPi - std::acos(tmp));
    const double t = mod(-a - std::atan2(ca - cb, d + sa - sb) + p / 2);
    best = std::min(best, t + p + mod(mod(b) - a - t + p));
  }
  return best * radius;
}

}  // namespace terratraj::ocp::testing
