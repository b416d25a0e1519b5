#pragma once
// Deadline: a wall-clock budget with an optional outside stop (SIGINT), what a computation of
// several solves asks between them: how long is left, and whether to stop.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>

namespace terratraj::ocp {

/// The reason every solver gives when a stop (SIGINT) ended it.
inline constexpr const char* kStoppedOnRequest = "stopped on request (SIGINT)";

/// A budget of `limit_s` seconds from `started` (absent: none), cut short when `stop` (may be
/// null) is set. Cheap to copy; the stop flag is not owned.
class Deadline {
 public:
  using Clock = std::chrono::steady_clock;

  /// A budget starting now.
  explicit Deadline(std::optional<double> limit_s, const std::atomic<bool>* stop = nullptr)
      : Deadline(Clock::now(), limit_s, stop) {}
  /// A budget that started at `started`.
  Deadline(Clock::time_point started, std::optional<double> limit_s,
           const std::atomic<bool>* stop = nullptr)
      : started_(started), limit_s_(limit_s), stop_(stop) {}

  /// Seconds since the start [s].
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - started_).count(); }
  /// Seconds left [s], never below 0; absent without a limit.
  std::optional<double> left() const {
    if (!limit_s_) return std::nullopt;
    return std::max(0.0, *limit_s_ - elapsed());
  }
  /// Whether the limit has passed or a stop was requested.
  bool over() const {
    return (stop_ != nullptr && stop_->load()) || (limit_s_ && elapsed() >= *limit_s_);
  }
  std::optional<double> limit() const { return limit_s_; }  ///< [s]
  const std::atomic<bool>* stop() const { return stop_; }

 private:
  Clock::time_point started_;
  std::optional<double> limit_s_;
  const std::atomic<bool>* stop_;
};

}  // namespace terratraj::ocp
