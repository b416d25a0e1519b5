#pragma once
// SolveAccounting: the wall clock and integration count of one solve and how it ends, shared
// by the solvers (not installed).

#include <chrono>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "terratraj/ocp/parametric_trajectory_model.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp::detail {

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
  /// Whether an optional time limit [s] has passed.
  bool pastTimeLimit(const std::optional<double>& limit_s) const {
    return limit_s && elapsedSeconds() > *limit_s;
  }
  /// Completes the result and returns a copy of it.
  SolveResult finish(SolveStatus status, std::string reason) const {
    result_->status = status;
    result_->reason = std::move(reason);
    result_->solve_time_ms = 1e3 * elapsedSeconds();
    result_->integrations = model_->integrations() - integrations_before_;
    return *result_;
  }
  /// finish() with kMaxIterations for a solve stopped by `limit_s` [s]: the reason names it
  /// and the result says so (time_limit_reached: an unfinished iterate, more time may differ).
  SolveResult finishOnTimeLimit(double limit_s) const {
    result_->time_limit_reached = true;
    return finish(SolveStatus::kMaxIterations,
                  "time limit of " + std::to_string(limit_s) + " s reached");
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
