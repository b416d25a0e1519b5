#pragma once
// RefinementOptions: how a CandidateRefiner refines (method, intervals, clearance, margins,
// corridor, time limit), their validation, and kAuto's rule for choosing the method.

#include <atomic>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"

namespace terratraj::refine {

/// How a candidate is refined.
enum class RefineMethod {
  kAuto,         ///< ipopt when polynomial controls suffice, else collocation (see below)
  kCollocation,  ///< Hermite-Simpson (or the configured scheme) warm-started from the candidate
  kShooting,     ///< multiple shooting warm-started from the candidate
  kNewton,       ///< polynomial controls by 004_...'s Newton: limits not enforced, only checked
  kIpopt,        ///< polynomial controls through Ipopt, limits enforced (sampled)
};
// The parametric methods (newton, ipopt) start from their own guess, not the candidate's shape:
// they suit short, open, simple candidates, where the candidate's class is the direct one.

/// "auto", "collocation", "shooting", "newton", "ipopt".
const char* refineMethodName(RefineMethod method);
/// Parses a method name; std::nullopt if it is not one.
std::optional<RefineMethod> parseRefineMethod(std::string_view name);
/// Every method name, in declaration order.
std::vector<std::string> refineMethodNames();

/// Settings of a CandidateRefiner.
struct RefinementOptions {
  RefineMethod method = RefineMethod::kAuto;
  /// Wall clock of one refine() [s], >= 0, absent = none: every solve, retry and the
  /// re-simulation share it (a solve gets what is left).
  std::optional<double> time_limit_s;
  /// A candidate whose first point is farther than this from the start, or whose last point is
  /// farther than this from the goal, is refused (kError) [m], > 0.
  double endpoint_tolerance_m = 0.5;
  /// A refinement is worse than its feasible candidate when its cost exceeds the candidate's
  /// (credited with its last point's distance to the exact goal at v_max) by more than this
  /// fraction, >= 0: the margins and the discretisation put the refinement's optimum a few
  /// tenths of a per cent above the true one, and the credit is optimistic.
  double worse_tolerance = 0.01;
  /// Set from outside to stop a refinement early (SIGINT): it ends with what it has.
  const std::atomic<bool>* stop = nullptr;
  /// Direct transcription: one interval per this much candidate length [m], > 0 ...
  double interval_length_m = 0.25;
  int min_intervals = 20;   ///< ... but at least this many, >= 1
  int max_intervals = 800;  ///< ... and at most this many, >= min_intervals
  /// For a candidate whose shortcut guess is used (a wiggly one) or whose guess is slower than
  /// warm_start_time_ratio x the bang-bang time along its path (a slow one), a first solve on a
  /// coarse mesh (one interval per this much length [m], > 0), whose solution (when it
  /// converges) starts the fine one; skipped when it would not halve the intervals.
  double coarse_interval_length_m = 1.0;
  /// Clearance kept from lethal and no-data cells [m], >= 0; lowered to half the candidate's
  /// own smallest clearance when that is less (a candidate through a narrow gap stays
  /// feasible); raised to half a cell (at most this) when the re-simulation clips a lethal cell.
  double min_clearance_m = 0.25;
  /// kAuto picks ipopt (polynomial controls) only for candidates at most this long [m] ...
  double parametric_max_length_m = 10.0;
  /// ... whose every sample is at least this far from impassable cells [m] ...
  double parametric_min_clearance_m = 3.0;
  /// ... and whose curvature changes sign at most this many times (a quartic yaw rate).
  int parametric_max_curvature_sign_changes = 2;
  /// Direct transcription settings (scheme, iterations, time limit, tolerances; the number of
  /// intervals and the clearance are set per candidate).
  ocp::DirectTranscriptionOptions transcription = [] {
    ocp::DirectTranscriptionOptions options;
    options.max_iterations = 500;
    options.linear_controls = true;
    return options;
  }();
  /// The fine direct-transcription solve starts Ipopt's barrier warm
  /// (ocp::TranscriptionBarrier::kWarm: monotone from a small mu) when its guess is near a
  /// local optimum: the coarse mesh's converged solution, or a guess whose duration is at most
  /// this multiple of the bang-bang time along its own path (accelerating and braking at a_max
  /// to and from v_max, 001_... IV.A), >= 1. Else Ipopt's adaptive barrier. A slower guess is
  /// first solved on the coarse mesh (coarse_interval_length_m).
  double warm_start_time_ratio = 1.1;
  /// Direct transcription imposes the limits at its points only: it is solved with kappa_max,
  /// sigma_max, pitch_max and roll_max lowered by this fraction, in [0, 0.5), so that the
  /// re-simulated trajectory holds the true limits between the points too ...
  double limit_margin = 0.02;
  /// ... and with v_max and omega_max lowered by this fraction, in [0, 0.5) (the speed is
  /// quadratic between points; the overshoot measured at 0.25 m intervals is about 0.1 %).
  double speed_margin = 0.0005;
  /// A re-simulation that still breaks a limit (the verdict's 1e-3 relative) is
  /// solved again from its own solution, up to this many times, >= 0: with the clearance
  /// raised to half a cell if it clipped a lethal cell; else first with twice the intervals
  /// (within max_intervals), then with the speed margin x 4 and the others x 2 (at most 0.25).
  int margin_retries = 3;
  /// The parametric solvers' settings (newton, ipopt; the method is set per refinement), and
  /// the terminal tolerances and limit tolerance of every method.
  ocp::BoundaryValueOptions parametric;
  /// Sampling of the candidate's derived speed profile for an x,y path [m].
  double guess_spacing_m = 0.25;
  /// A converged refinement that left the candidate's class is solved again from the candidate
  /// inside a corridor: the cells within this distance of it [m], > 0 (0: no retry), the rest
  /// made impassable for the clearance constraint. A path in the corridor can only leave the
  /// class through an obstacle inside it.
  double corridor_radius_m = 1.0;
  /// The optimiser starts from the candidate's shortcut path (greedy straight segments that
  /// keep this clearance from impassable cells [m], > 0; 0: never) when that is shorter than
  /// shortcut_gain x the candidate's length and in the same class: loops and detours of a
  /// wiggly candidate cost iterations and can trap the optimiser.
  double shortcut_clearance_m = 0.35;
  double shortcut_gain = 0.95;  ///< in (0, 1]
};

/// Why the options cannot be used, or std::nullopt.
std::optional<std::string> validateRefinementOptions(const RefinementOptions& options);

/// kAuto's rule for one candidate of planar length `length_m`, smallest clearance
/// `min_clearance_m` and `curvature_sign_changes`: ipopt (polynomial controls) when all three
/// are within the options' parametric_* bounds, else collocation; a configured method is returned
/// as it is. Writes the reason into `rule`. A failed ipopt falls back to collocation.
RefineMethod chooseRefineMethod(const RefinementOptions& options, double length_m,
                                double min_clearance_m, int curvature_sign_changes,
                                std::string& rule);

}  // namespace terratraj::refine
