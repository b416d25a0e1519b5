#pragma once
// What both Ipopt adapters share (the collocation NLP in direct_transcription.cpp, the parametric
// NLP in ipopt_solver.cpp): the base options, the one table from Ipopt's return statuses to
// terratraj's, the callback guard and the rule for the rows that vanish at an end at rest. Not
// installed; needs HAVE_CSTDDEF like every Ipopt header (set for terratraj_ocp).

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpReturnCodes.hpp>

#include <optional>
#include <string>
#include <string_view>

#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::ocp::detail {

/// Ipopt's default nlp_{lower,upper}_bound_inf: a bound at or beyond it is no bound.
inline constexpr double kIpoptInfinity = 1e19;

/// Ipopt's name of a status ("Solve_Succeeded", ...).
const char* ipoptStatusName(Ipopt::ApplicationReturnStatus status);

/// The settings every terratraj Ipopt solve shares.
struct IpoptBaseSettings {
  int print_level = 0;                   ///< Ipopt's print_level, in [0, 12]
  int max_iterations = 100;              ///< Ipopt's max_iter
  std::optional<double> max_cpu_time_s;  ///< [s] Ipopt's max_cpu_time (clamped to >= 1e-6)
};

/// Sets the options both adapters share: no banner, print_level, MUMPS with the AMF ordering
/// (deterministic: MUMPS's automatic choice takes SCOTCH, which Debian builds with a varying
/// seed, so iteration counts varied from run to run; docs/optimal-control.md), max_iter and
/// max_cpu_time. False when Ipopt rejects one (a print_level out of range).
bool setBaseOptions(Ipopt::OptionsList& options, const IpoptBaseSettings& settings);

/// Initialises `app` with the developer's options file named by TERRATRAJ_IPOPT_OPTIONS (for
/// profiling Ipopt's settings, docs/optimal-control.md; its values override the adapters'), or
/// with none. False when Ipopt fails to initialise.
bool initializeIpopt(Ipopt::IpoptApplication& app);

/// terratraj's status for one of Ipopt's, with its reason.
struct IpoptOutcome {
  SolveStatus status = SolveStatus::kError;
  std::string reason;  ///< empty when converged
};

/// The one table from Ipopt's return status to terratraj's: Solve_Succeeded and
/// Solved_To_Acceptable_Level are converged (Ipopt's claim only: callers re-check the result);
/// the iteration limit, max_cpu_time and a stop from the adapter on its time limit (`timed_out`)
/// are max_iterations; Infeasible_Problem_Detected, Restoration_Failed and
/// Not_Enough_Degrees_Of_Freedom are infeasible (no feasible point near this start); the rest
/// that stop the iteration are diverged, and set-up failures error. `max_iterations` and
/// `time_limit_s` [s] go into the reasons; with `stopped` the reason of a timed-out solve says it
/// was stopped on request instead.
IpoptOutcome ipoptOutcome(Ipopt::ApplicationReturnStatus status, bool timed_out, int max_iterations,
                          std::optional<double> time_limit_s, bool stopped = false);

/// Runs `body` (returning bool) for an Ipopt callback: an exception becomes false, which Ipopt
/// treats as an evaluation failure (no exception crosses its C++ / Fortran frames).
template <typename Body>
bool guardedCallback(Body&& body) noexcept {
  try {
    return body();
  } catch (...) {
    return false;
  }
}

/// Whether the row named `limit` (PathConstraints::name, a transcription model's constraint
/// name) at the fixed end state `end` is identically 0 whatever the free variables: `end` stands
/// still with no yaw rate and the row vanishes there (vanishesAtRest). Such a row, active with
/// no free variable in it, leaves an interior-point method no interior (its multiplier went to
/// 2.7e9 on the Segway's rest-to-rest problems, which then never converged); both adapters free
/// it (no upper bound). The curvature at a rest end is held by the omega' / v' rows instead.
bool degenerateAtRestEnd(const VehicleState& end, std::string_view limit);

}  // namespace terratraj::ocp::detail
