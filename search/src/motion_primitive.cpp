#include "terratraj/search/motion_primitive.hpp"

#include <cmath>
#include <sstream>

#include "terratraj/search/goal_region.hpp"

namespace terratraj::search {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kEndTolerance = 1e-6;      // snapped ends are exact up to rounding [m]
constexpr double kHeadingTolerance = 2e-3;  // the solver's 1 mrad plus rounding [rad]

std::string describe(const MotionPrimitive& p, std::size_t index) {
  std::ostringstream text;
  text << "primitive " << index << " (heading " << p.start_heading << " -> " << p.end_heading
       << ", offset " << p.offset.x() << "," << p.offset.y() << ")";
  return text.str();
}

}  // namespace

double LatticeSpec::headingAngle(int k) const {
  return kTwoPi * static_cast<double>(wrapHeading(k)) / heading_count;
}

int LatticeSpec::wrapHeading(int k) const {
  const int r = k % heading_count;
  return r < 0 ? r + heading_count : r;
}

int LatticeSpec::nearestHeading(double heading) const {
  if (!std::isfinite(heading)) return 0;
  const double turns = heading / kTwoPi * heading_count;
  return wrapHeading(static_cast<int>(std::lround(std::fmod(turns, heading_count))));
}

std::optional<std::string> LatticeSpec::validate() const {
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    return "resolution: must be a finite number > 0 m";
  }
  if (heading_count < 4 || heading_count > 1024) {
    return "heading_count: must be in [4, 1024] (got " + std::to_string(heading_count) + ")";
  }
  return std::nullopt;
}

std::size_t PrimitiveSet::size() const {
  std::size_t n = 0;
  for (const auto& list : by_heading) n += list.size();
  return n;
}

std::optional<std::string> PrimitiveSet::checkAgainst(const LatticeSpec& wanted,
                                                      const models::VehicleLimits* limits) const {
  if (std::abs(lattice.resolution - wanted.resolution) > 1e-9 * wanted.resolution) {
    std::ostringstream text;
    text << "resolution_m: the primitives are for a " << lattice.resolution
         << " m lattice, the planner uses " << wanted.resolution << " m";
    return text.str();
  }
  if (lattice.heading_count != wanted.heading_count) {
    return "heading_count: the primitives are for " + std::to_string(lattice.heading_count) +
           " headings, the planner uses " + std::to_string(wanted.heading_count);
  }
  if (by_heading.size() != static_cast<std::size_t>(wanted.heading_count)) {
    return "primitives: lists for " + std::to_string(by_heading.size()) + " headings, expected " +
           std::to_string(wanted.heading_count);
  }
  std::size_t index = 0;
  for (int k = 0; k < wanted.heading_count; ++k) {
    if (by_heading[k].empty()) {
      return "primitives: heading " + std::to_string(k) + " has no primitive";
    }
    for (const MotionPrimitive& p : by_heading[k]) {
      const std::string name = describe(p, index++);
      if (p.start_heading != k) return name + ": start_heading differs from its list";
      if (p.end_heading < 0 || p.end_heading >= wanted.heading_count) {
        return name + ": end_heading out of range";
      }
      if (p.offset.isZero()) return name + ": offset is zero";
      if (p.samples.size() < 2) return name + ": fewer than 2 samples";
      const PrimitiveSample& first = p.samples.front();
      const PrimitiveSample& last = p.samples.back();
      if (std::hypot(first.x, first.y) > kEndTolerance ||
          std::abs(wrapAngle(first.heading - wanted.headingAngle(k))) > kHeadingTolerance) {
        return name + ": the first sample is not the start node and heading";
      }
      const Eigen::Vector2d end = p.offset.cast<double>() * wanted.resolution;
      if (std::hypot(last.x - end.x(), last.y - end.y()) > kEndTolerance ||
          std::abs(wrapAngle(last.heading - wanted.headingAngle(p.end_heading))) >
              kHeadingTolerance) {
        return name + ": the last sample is not the end node and heading";
      }
      for (std::size_t i = 0; i < p.samples.size(); ++i) {
        const PrimitiveSample& q = p.samples[i];
        if (!(std::isfinite(q.s) && std::isfinite(q.t) && std::isfinite(q.x) &&
              std::isfinite(q.y) && std::isfinite(q.heading) && std::isfinite(q.curvature))) {
          return name + ": sample " + std::to_string(i) + " is not finite";
        }
        if (i > 0 && !(q.s > p.samples[i - 1].s)) {
          return name + ": arc length not increasing at sample " + std::to_string(i);
        }
      }
      if (std::abs(first.curvature) > 1e-6 || std::abs(last.curvature) > 1e-6) {
        return name + ": curvature is not zero at both ends";
      }
      if (limits != nullptr && p.max_abs_curvature > limits->kappa_max * (1.0 + 1e-6)) {
        std::ostringstream text;
        text << name << ": curvature " << p.max_abs_curvature << " exceeds kappa_max "
             << limits->kappa_max;
        return text.str();
      }
    }
  }
  return std::nullopt;
}

}  // namespace terratraj::search
