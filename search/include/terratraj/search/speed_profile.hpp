#pragma once
// SpeedProfile: the bang-bang speed profile along a sampled path (001_... IV.C: maximum
// acceleration, then maximum braking), under a speed cap at every sample.
//
// Forward pass: v[i+1] = min(cap[i+1], sqrt(v[i]^2 + 2 a_max ds[i])) from the start speed;
// backward pass: v[i] = min(v[i], sqrt(v[i+1]^2 + 2 a_max ds[i])) from the wished end speed.
// v^2 is linear in arc length inside each segment, so the acceleration there is constant and
// within a_max; the segment time is 2 ds / (v[i] + v[i+1]). The result is the time-optimal
// profile for the path under the caps.

#include <cstddef>
#include <vector>

namespace terratraj::search {

/// Outcome of SpeedProfile::compute().
enum class SpeedProfileStatus {
  kOk,
  kStartAboveCap,  ///< the start speed exceeds the cap at the first sample
  kCannotBrake,    ///< the path is too short to brake to a later cap or to the end speed
  kStall,          ///< a cap is below the minimum moving speed: the path cannot be driven
};

/// Name of a SpeedProfileStatus ("ok", "start_above_cap", "cannot_brake", "stall").
const char* speedProfileStatusName(SpeedProfileStatus status);

/// Caps below this speed [m/s] count as a stall (the segment time would be unbounded).
inline constexpr double kMinCapSpeed = 1e-3;

/// Computes and holds a profile. Reuse one object: its buffers are kept between calls.
class SpeedProfile {
 public:
  /// Profile over n + 1 samples: `segment_lengths` has n values [m] (> 0), `caps` n + 1 [m/s].
  /// The first speed is `v_start`; the last is at most `v_end` (lower only when the path is
  /// too short to accelerate to it). Fails with a status (see SpeedProfileStatus).
  SpeedProfileStatus compute(const std::vector<double>& segment_lengths,
                             const std::vector<double>& caps, double v_start, double v_end,
                             double a_max);

  /// Speed at each sample [m/s].
  const std::vector<double>& speeds() const { return speeds_; }
  /// Time at each sample from the first [s].
  const std::vector<double>& times() const { return times_; }
  /// Total time [s].
  double duration() const { return times_.empty() ? 0.0 : times_.back(); }

 private:
  std::vector<double> speeds_;
  std::vector<double> times_;
};

}  // namespace terratraj::search
