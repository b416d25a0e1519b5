#pragma once
// AttemptLog (internal to refine/src): the attempts of one solveSeeded() and the best of them so
// far (converged first, then the lower verified cost).

#include <chrono>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "terratraj/refine/seeded_solver.hpp"

namespace terratraj::refine::detail {

// Keeps the better of the best so far and a new result: converged first, then the lower cost.
inline bool better(const SeededSolution& candidate, const SeededSolution& best) {
  const bool c = candidate.status == ocp::SolveStatus::kConverged;
  const bool b = best.status == ocp::SolveStatus::kConverged;
  if (c != b) return c;
  if (!best.verified.ok) return candidate.verified.ok;
  return candidate.verified.ok && candidate.verified.cost < best.verified.cost;
}

// The attempts of one solveSeeded() and the best of them so far.
class AttemptLog {
 public:
  using Clock = std::chrono::steady_clock;

  AttemptLog(CoreMethod method, std::function<void(const SeedAttempt&)> on_attempt)
      : on_attempt_(std::move(on_attempt)) {
    best_.method = coreMethodName(method);
    best_.reason = "no attempt was made";
  }

  // Adds `result`, started at `attempt_started`, and tells `on_attempt`; `candidate` false:
  // listed among the attempts, never the result (a bridge's first step when a clearance is
  // asked for).
  void record(SeededSolution result, Clock::time_point attempt_started, bool candidate = true) {
    SeedAttempt a;
    a.seed = result.initial_guess;
    a.method = result.method;
    a.status = result.status;
    a.reason = result.reason;
    a.cost = result.verified.ok ? result.verified.cost : std::numeric_limits<double>::quiet_NaN();
    a.time_ms = 1e3 * std::chrono::duration<double>(Clock::now() - attempt_started).count();
    a.budget_s = budget_s;
    a.time_given_s = time_given_s;
    a.round = round;
    a.time_limit_reached = result.time_limit_reached;
    const int iterations = best_.iterations + result.iterations;
    const bool first_candidate = !any_candidate_;
    any_candidate_ = any_candidate_ || candidate;
    std::vector<SeedAttempt> attempts = std::move(best_.attempts);
    attempts.push_back(a);
    if (candidate && (first_candidate || better(result, best_))) best_ = std::move(result);
    best_.attempts = std::move(attempts);
    best_.iterations = iterations;
    if (on_attempt_) on_attempt_(a);
  }

  bool converged() const { return best_.status == ocp::SolveStatus::kConverged; }
  bool empty() const { return best_.attempts.empty(); }
  SeededSolution& best() { return best_; }

  double budget_s = std::numeric_limits<double>::infinity();  ///< of the seed being tried [s]
  /// budget_s capped by the solve's time left, for the seed being tried [s]
  double time_given_s = std::numeric_limits<double>::infinity();
  int round = 0;  ///< of the seed being tried

 private:
  std::function<void(const SeedAttempt&)> on_attempt_;
  SeededSolution best_;
  bool any_candidate_ = false;
};

}  // namespace terratraj::refine::detail
