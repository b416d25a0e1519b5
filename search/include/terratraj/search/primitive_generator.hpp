#pragma once
// Generation of a lattice's motion primitives with the parametric boundary-value solver
// (ocp::solveBoundaryValue, 004_... 3) on flat ground, at constant speed, minimum time.
//
// For each start heading k and each requested turn d (heading-index change), the target end
// heading is k + d; a reference length is the shortest symmetric clothoid turn that the
// curvature-rate bound allows (times a margin); candidate end positions are the lattice offsets
// whose chord is at least that turn's and whose misalignment an S-bend of the remaining length
// can absorb, shortest first; the boundary-value problem (Ipopt, limits enforced) from
// (0, 0, heading k) to a candidate position and heading
// is solved. When every candidate fails, the reference length grows by 25 % (up to `attempts`
// times) and the new candidates are tried. Straight moves
// (d = 0) come in the lengths listed in straight_lengths. When heading_count is a multiple of 4,
// the primitives of headings k + heading_count / 4 are those of k rotated by 90 degrees (exact
// on the grid), so only a quarter of the headings are solved.

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/search/motion_primitive.hpp"

namespace terratraj::search {

/// What to generate.
struct PrimitiveGenerationOptions {
  std::vector<int> turns = {-2, -1, 1, 2};            ///< heading-index changes (0 excluded here)
  std::vector<double> straight_lengths = {1.0, 2.0};  ///< d = 0 moves [m] (rounded to the grid)
  /// Constant speed of the primitives [m/s]; the primitives respect sigma_max and omega_max at
  /// this speed (faster driving is capped by the planner). <= 0: the vehicle's v_max.
  double speed = 0.0;
  double length_margin = 1.15;  ///< reference turn length over the clothoid minimum, >= 1
  /// Candidate offsets per reference length (shortest first), and reference lengths (each 25 %
  /// longer, when every offset of the previous one failed), >= 1.
  int attempts = 4;
  double sample_spacing = 0.05;  ///< stored sample spacing [m], > 0
  int max_iterations = 100;      ///< of each boundary-value solve
  /// Called after each solved heading with (headings done, headings to solve); may be empty.
  /// The generation takes seconds: the CLI prints a progress line from it.
  std::function<void(int, int)> progress;
  /// Set from outside (SIGINT) to stop: the headings not yet solved get no primitive.
  const std::atomic<bool>* stop = nullptr;
};

/// A generated set and what failed.
struct PrimitiveGenerationResult {
  PrimitiveSet set;
  std::vector<std::string> failures;  ///< one line per (heading, turn) that got no primitive
};

/// Generates the primitives of `lattice` for a vehicle of `limits` (only v_max, omega_max,
/// kappa_max and sigma_max matter on flat ground). Deterministic. Never throws; a heading that
/// gets no primitive at all is listed in `failures` (and the set fails checkAgainst()).
PrimitiveGenerationResult generatePrimitives(const LatticeSpec& lattice,
                                             const models::VehicleLimits& limits,
                                             const PrimitiveGenerationOptions& options = {});

/// One flat-ground minimum-time trajectory at constant `speed` from (0, 0, start_heading) to
/// (end.x, end.y, end_heading) [m, rad], with zero curvature at both ends, sampled every
/// `sample_spacing` metres; its end snapped exactly onto `end` (the solver leaves < 1 mm).
/// std::nullopt when the solve does not converge within the limits. Used for the primitives and
/// for the planner's connectors from a start heading that is not a lattice heading.
std::optional<MotionPrimitive> solvePrimitive(double start_heading, const Eigen::Vector2d& end,
                                              double end_heading, double speed,
                                              const models::VehicleLimits& limits,
                                              double sample_spacing, int max_iterations = 100);

}  // namespace terratraj::search
