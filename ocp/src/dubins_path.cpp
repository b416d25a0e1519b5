#include "terratraj/ocp/dubins_path.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace terratraj::ocp {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;

// An angle in [0, 2 pi); rounding just below 2 pi is taken as 0 (a zero-length arc).
double mod2pi(double a) {
  const double r = a - kTwoPi * std::floor(a / kTwoPi);
  return r > kTwoPi - 1e-9 ? 0.0 : r;
}

// The segment types of each word: +1 left, -1 right, 0 straight.
std::array<int, 3> segmentTypes(DubinsWord word) {
  switch (word) {
    case DubinsWord::kLSL:
      return {1, 0, 1};
    case DubinsWord::kRSR:
      return {-1, 0, -1};
    case DubinsWord::kLSR:
      return {1, 0, -1};
    case DubinsWord::kRSL:
      return {-1, 0, 1};
    case DubinsWord::kRLR:
      return {-1, 1, -1};
    case DubinsWord::kLRL:
      return {1, -1, 1};
  }
  return {0, 0, 0};
}

// Normalised segment lengths (t, p, q) of a word, in units of the radius; std::nullopt when
// the word does not connect the poses. `d` is the normalised distance, `a`, `b` the headings
// relative to the line between them (Shkel & Lumelsky).
std::optional<std::array<double, 3>> wordLengths(DubinsWord word, double d, double a, double b) {
  const double sa = std::sin(a), sb = std::sin(b), ca = std::cos(a), cb = std::cos(b);
  const double cab = std::cos(a - b);
  switch (word) {
    case DubinsWord::kLSL: {
      const double p2 = 2 + d * d - 2 * cab + 2 * d * (sa - sb);
      if (p2 < -1e-10) return std::nullopt;
      const double tmp = std::atan2(cb - ca, d + sa - sb);
      return std::array<double, 3>{mod2pi(-a + tmp), std::sqrt(std::max(p2, 0.0)), mod2pi(b - tmp)};
    }
    case DubinsWord::kRSR: {
      const double p2 = 2 + d * d - 2 * cab + 2 * d * (sb - sa);
      if (p2 < -1e-10) return std::nullopt;
      const double tmp = std::atan2(ca - cb, d - sa + sb);
      return std::array<double, 3>{mod2pi(a - tmp), std::sqrt(std::max(p2, 0.0)), mod2pi(-b + tmp)};
    }
    case DubinsWord::kLSR: {
      const double p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb);
      if (p2 < -1e-10) return std::nullopt;
      const double p = std::sqrt(std::max(p2, 0.0));
      const double tmp = std::atan2(-ca - cb, d + sa + sb) - std::atan2(-2.0, p);
      return std::array<double, 3>{mod2pi(-a + tmp), p, mod2pi(-mod2pi(b) + tmp)};
    }
    case DubinsWord::kRSL: {
      const double p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb);
      if (p2 < -1e-10) return std::nullopt;
      const double p = std::sqrt(std::max(p2, 0.0));
      const double tmp = std::atan2(ca + cb, d - sa - sb) - std::atan2(2.0, p);
      return std::array<double, 3>{mod2pi(a - tmp), p, mod2pi(b - tmp)};
    }
    case DubinsWord::kRLR: {
      const double tmp = (6 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8;
      if (std::abs(tmp) > 1) return std::nullopt;
      const double p = mod2pi(kTwoPi - std::acos(tmp));
      const double t = mod2pi(a - std::atan2(ca - cb, d - sa + sb) + p / 2);
      return std::array<double, 3>{t, p, mod2pi(a - b - t + p)};
    }
    case DubinsWord::kLRL: {
      const double tmp = (6 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8;
      if (std::abs(tmp) > 1) return std::nullopt;
      const double p = mod2pi(kTwoPi - std::acos(tmp));
      const double t = mod2pi(-a - std::atan2(ca - cb, d + sa - sb) + p / 2);
      return std::array<double, 3>{t, p, mod2pi(mod2pi(b) - a - t + p)};
    }
  }
  return std::nullopt;
}

}  // namespace

const char* dubinsWordName(DubinsWord word) {
  switch (word) {
    case DubinsWord::kLSL:
      return "LSL";
    case DubinsWord::kRSR:
      return "RSR";
    case DubinsWord::kLSR:
      return "LSR";
    case DubinsWord::kRSL:
      return "RSL";
    case DubinsWord::kRLR:
      return "RLR";
    case DubinsWord::kLRL:
      return "LRL";
  }
  return "?";
}

PathPoint2 DubinsPath::at(double s) const {
  s = std::clamp(s, 0.0, length());
  const std::array<int, 3> types = segmentTypes(word);
  PathPoint2 p;
  p.s = s;
  double x = start.x, y = start.y, h = start.heading;
  double left = s;
  for (int k = 0; k < 3; ++k) {
    const double l = std::min(left, lengths[k]);
    const int turn = types[k];
    if (turn == 0) {
      x += l * std::cos(h);
      y += l * std::sin(h);
    } else {
      const double dh = turn * l / radius;
      x += radius * turn * (std::sin(h + dh) - std::sin(h));
      y += radius * turn * (-std::cos(h + dh) + std::cos(h));
      h += dh;
    }
    p.curvature = turn / radius;
    left -= l;
    if (left <= 0.0) break;
  }
  p.x = x;
  p.y = y;
  p.heading = h;
  return p;
}

std::vector<PathPoint2> DubinsPath::sample(double spacing) const {
  const double total = length();
  const int n = std::max(1, static_cast<int>(std::ceil(total / spacing - 1e-9)));
  std::vector<PathPoint2> points;
  points.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) points.push_back(at(total * i / n));
  return points;
}

std::vector<DubinsPath> dubinsPaths(const PlanePose& from, const PlanePose& to, double radius) {
  std::vector<DubinsPath> paths;
  if (!(radius > 0.0) || !std::isfinite(radius)) return paths;
  const double dx = (to.x - from.x) / radius, dy = (to.y - from.y) / radius;
  const double d = std::hypot(dx, dy);
  const double theta = d > 0.0 ? mod2pi(std::atan2(dy, dx)) : 0.0;
  const double a = mod2pi(from.heading - theta), b = mod2pi(to.heading - theta);
  for (DubinsWord word : {DubinsWord::kLSL, DubinsWord::kRSR, DubinsWord::kLSR, DubinsWord::kRSL,
                          DubinsWord::kRLR, DubinsWord::kLRL}) {
    const std::optional<std::array<double, 3>> t = wordLengths(word, d, a, b);
    if (!t) continue;
    DubinsPath path;
    path.start = from;
    path.word = word;
    path.radius = radius;
    for (int k = 0; k < 3; ++k) path.lengths[k] = (*t)[k] * radius;
    // The closed form can return a word that misses the goal by rounding: keep the ones that
    // reach it.
    const PathPoint2 end = path.at(path.length());
    const double heading_error = std::remainder(end.heading - to.heading, kTwoPi);
    if (std::hypot(end.x - to.x, end.y - to.y) > 1e-6 * std::max(1.0, radius) ||
        std::abs(heading_error) > 1e-6) {
      continue;
    }
    paths.push_back(path);
  }
  std::sort(paths.begin(), paths.end(),
            [](const DubinsPath& p, const DubinsPath& q) { return p.length() < q.length(); });
  return paths;
}

}  // namespace terratraj::ocp
