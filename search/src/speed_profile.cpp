#include "terratraj/search/speed_profile.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::search {

const char* speedProfileStatusName(SpeedProfileStatus status) {
  switch (status) {
    case SpeedProfileStatus::kOk:
      return "ok";
    case SpeedProfileStatus::kStartAboveCap:
      return "start_above_cap";
    case SpeedProfileStatus::kCannotBrake:
      return "cannot_brake";
    case SpeedProfileStatus::kStall:
      return "stall";
  }
  return "unknown";
}

SpeedProfileStatus SpeedProfile::compute(const std::vector<double>& segment_lengths,
                                         const std::vector<double>& caps, double v_start,
                                         double v_end, double a_max) {
  const std::size_t n = segment_lengths.size();
  speeds_.assign(n + 1, 0.0);
  times_.assign(n + 1, 0.0);
  // Relative slack for rounding when the start speed sits exactly on a cap.
  constexpr double kSlack = 1e-12;
  if (v_start > caps[0] * (1.0 + kSlack)) return SpeedProfileStatus::kStartAboveCap;
  for (std::size_t i = 1; i <= n; ++i) {
    if (caps[i] < kMinCapSpeed) return SpeedProfileStatus::kStall;
  }
  speeds_[0] = std::min(v_start, caps[0]);
  for (std::size_t i = 0; i < n; ++i) {
    const double reach = std::sqrt(speeds_[i] * speeds_[i] + 2.0 * a_max * segment_lengths[i]);
    speeds_[i + 1] = std::min(caps[i + 1], reach);
  }
  speeds_[n] = std::min(speeds_[n], std::max(0.0, v_end));
  for (std::size_t i = n; i-- > 0;) {
    const double brake =
        std::sqrt(speeds_[i + 1] * speeds_[i + 1] + 2.0 * a_max * segment_lengths[i]);
    if (brake < speeds_[i]) speeds_[i] = brake;
  }
  if (speeds_[0] < v_start * (1.0 - kSlack) - kSlack) return SpeedProfileStatus::kCannotBrake;
  speeds_[0] = v_start;
  for (std::size_t i = 0; i < n; ++i) {
    const double mean = 0.5 * (speeds_[i] + speeds_[i + 1]);
    if (mean <= 0.0) return SpeedProfileStatus::kStall;
    times_[i + 1] = times_[i] + segment_lengths[i] / mean;
  }
  return SpeedProfileStatus::kOk;
}

}  // namespace terratraj::search
