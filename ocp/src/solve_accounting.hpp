#pragma once
// SolveAccounting: the wall clock and integration count of one solve and how it ends, shared
// by the solvers (not installed).

#include <atomic>
#include <chrono>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp::detail {

/// Why a solve ended early: "stopped on request" when `stop` (may be null) is set, else its time
/// limit [s].
inline std::string stopReason(const std::optional<double>& limit_s, const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load()) return kStoppedOnRequest;
  return "time limit of " + std::to_string(limit_s.value_or(0.0)) + " s reached";
}

/// Starts the clock on construction; finish() fills the result's status, reason, time and
/// integrations used since construction.
class SolveAccounting {
 public:
  SolveAccounting(const ParametricTrajectoryModel& model, SolveResult& result, const char* method)
      : started_(std::chrono::steady_clock::now()),
        model_(&model),
        integrations_before_(model.integrations()),
        result_(&result) {
    result.method = method;
  }

  /// Seconds since construction.
  double elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  }
  /// Whether an optional time limit [s] has passed or a stop (may be null) was requested.
  bool pastTimeLimit(const std::optional<double>& limit_s,
                     const std::atomic<bool>* stop = nullptr) const {
    return (stop != nullptr && stop->load()) || (limit_s && elapsedSeconds() > *limit_s);
  }
  /// Completes the result and returns a copy of it.
  SolveResult finish(SolveStatus status, std::string reason) const {
    result_->status = status;
    result_->reason = std::move(reason);
    result_->solve_time_ms = 1e3 * elapsedSeconds();
    result_->integrations = model_->integrations() - integrations_before_;
    return *result_;
  }
  /// finish() with kMaxIterations for a solve stopped by `limit_s` [s] or by `stop`: the reason
  /// names which and the result says so (time_limit_reached: an unfinished iterate, more time
  /// may differ).
  SolveResult finishOnTimeLimit(const std::optional<double>& limit_s,
                                const std::atomic<bool>* stop = nullptr) const {
    result_->time_limit_reached = true;
    return finish(SolveStatus::kMaxIterations, stopReason(limit_s, stop));
  }

 private:
  std::chrono::steady_clock::time_point started_;
  const ParametricTrajectoryModel* model_;
  long integrations_before_;
  SolveResult* result_;
};

/// Runs `run()`; an exception escaping a third-party library (`library` names it) becomes
/// kError instead of leaving the solver.
template <typename Run>
SolveResult guardThirdParty(const char* library, const SolveAccounting& accounting, Run&& run) {
  try {
    return run();
  } catch (const std::exception& error) {
    return accounting.finish(SolveStatus::kError,
                             std::string(library) + ": unexpected exception: " + error.what());
  } catch (...) {
    return accounting.finish(SolveStatus::kError, std::string(library) + ": unexpected exception");
  }
}

}  // namespace terratraj::ocp::detail
