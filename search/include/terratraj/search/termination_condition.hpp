#pragma once
// TerminationCondition: when a planner's solve() stops (OMPL's PlannerTerminationCondition):
// a wall-clock limit, optionally an iteration budget (deterministic runs) and / or the first
// solution.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <limits>

namespace terratraj::search {

/// Stopping rules of one solve(). Value type; the clock starts when solve() calls start().
class TerminationCondition {
 public:
  using Clock = std::chrono::steady_clock;

  /// Stop after `seconds` of wall-clock time (>= 0; 0 means no search at all; NaN or negative
  /// are treated as 0).
  static TerminationCondition timeLimit(double seconds);
  /// Stop after `iterations` milestones (no time limit): deterministic for a seed.
  static TerminationCondition iterationLimit(std::size_t iterations);

  /// Also stop once a first solution is found.
  TerminationCondition& stopAtFirstSolution(bool stop = true) {
    stop_at_first_solution_ = stop;
    return *this;
  }
  /// Also stop as soon as `*flag` becomes true (SIGINT); null: never. The flag must outlive
  /// the solve.
  TerminationCondition& stopFlag(const std::atomic<bool>* flag) {
    stop_flag_ = flag;
    return *this;
  }
  /// Also stop after `iterations` milestones.
  TerminationCondition& maxIterations(std::size_t iterations) {
    max_iterations_ = iterations;
    return *this;
  }

  /// Starts the clock (solve() calls it).
  void start() { start_ = Clock::now(); }
  /// Seconds since start().
  double elapsedSeconds() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }
  /// Whether the clock has run out, or a stop was requested through the flag.
  bool timeUp() const {
    return elapsedSeconds() >= time_limit_s_ || (stop_flag_ != nullptr && stop_flag_->load());
  }
  /// Whether a stop was requested through the flag.
  bool stopRequested() const { return stop_flag_ != nullptr && stop_flag_->load(); }
  /// Whether to stop after `iterations` milestones, with or without a solution.
  bool shouldStop(std::size_t iterations, bool solved) const {
    return iterations >= max_iterations_ || (solved && stop_at_first_solution_) || timeUp();
  }

  /// The wall-clock limit [s] (+infinity for none).
  double timeLimitSeconds() const { return time_limit_s_; }
  /// The iteration budget (SIZE_MAX for none).
  std::size_t iterationLimit() const { return max_iterations_; }
  /// Whether solve() stops at the first solution.
  bool stopsAtFirstSolution() const { return stop_at_first_solution_; }

 private:
  double time_limit_s_ = std::numeric_limits<double>::infinity();
  std::size_t max_iterations_ = std::numeric_limits<std::size_t>::max();
  bool stop_at_first_solution_ = false;
  Clock::time_point start_ = Clock::now();
  const std::atomic<bool>* stop_flag_ = nullptr;
};

}  // namespace terratraj::search
