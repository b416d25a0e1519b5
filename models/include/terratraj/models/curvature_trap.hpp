#pragma once
// CurvatureTrap: whether a pose is trapped by the turning radius. A goal on a side slope that
// the vehicle can only stand on at nearly its own heading may have no way in: every path that
// ends there, driven backwards from it, rolls beyond the limits within a metre (the davosdorf
// "pocket" of the robustness set, docs/benchmarks.md). checkGoalReachability()'s search over
// (cell, heading sector) lets the vehicle turn within a cell without moving, so it cannot see
// that; this check bounds the curvature.
//
// The relaxation. A forward-driving vehicle parametrised by its horizontal arc length sigma
// moves with d(x, y)/d sigma = (cos heading, sin heading) and turns with
// |d heading / d sigma| <= kappa_max / cos^2(pitch) (x' = v cos(heading) cos(pitch),
// heading' = omega cos(roll) / cos(pitch), |omega| <= kappa_max v), so at most kappa =
// kappa_max / cos^2(pitch bound) while it stays within its pitch bound. Speeds, rates and the
// tables only remove paths. The check searches a square window around the pose, split into
// boxes (a position square of `box_m` and a heading interval of 2 pi / `heading_bins`). A box
// is refused when no pose in it can be within the limits: the attitude at its centre and the
// first-order bound of its Jacobian over the box leave |pitch| or |roll| above (1 +
// `limit_tolerance`) x the limit everywhere in it, or all of it lies on lethal, no-data or
// off-map cells. From a box, the poses one `step_m` of arc length on (or back, for paths that
// arrive at the pose) lie in an interval hull computed from the heading interval widened by
// kappa sigma (sound: cos and sin bounded over each sub-step); the successors are the boxes
// that meet it and are not refused; a box is dropped when, at an intermediate arc length, no
// box its hull meets is admissible (every path from it dies there). Every admissible path is
// thus a chain of successors, so when the search exhausts a region that neither meets the
// window's edge nor holds the other end's pose, no admissible path leaves (or enters) the pose:
// the goal is unreachable. "Escapes" and "reaches the other end" prove nothing (the hulls and
// the boxes over-approximate: the hulls' blur lets a chain of boxes turn about a third more
// sharply than the vehicle can at the defaults).
//
// Sizes. The attitude changes by up to 3 rad/m on rough DEMs at rover scale (davosdorf at
// 0.25 m cells), so a box of 1 cm spreads it by about 2 deg, and the second-order term over a
// sub-box of 2 cm (about 0.2 deg there) stays within the 2 % slack. A pocket's walls there are
// 0.1-0.2 m thick ridges of pitch or roll, which moves of 0.1 m checked every 2 cm do not jump;
// a dead end of flat ground narrower than the turning circle is a larger region, which boxes
// of 2 cm settle within max_boxes (goal_reachability.hpp runs both sizes). Boxes are stored
// only when touched.

#include <cstddef>
#include <optional>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::models {

/// How finely and how far the curvature trap check searches.
struct CurvatureTrapOptions {
  double window_m = 2.0;          ///< half the side of the square searched around the pose [m], > 0
  double box_m = 0.01;            ///< side of a position box [m], > 0
  int heading_bins = 360;         ///< heading boxes over the circle, >= 8
  double step_m = 0.1;            ///< horizontal arc length of one move [m], > 2 box_m
  int step_checks = 5;            ///< arc lengths per move where admissibility is tested, 1..64
  double limit_tolerance = 0.02;  ///< relative slack on pitch_max and roll_max, >= 0
  /// Largest sub-box side over which the first-order bound of the attitude is trusted [m], > 0:
  /// a larger box is tested as its sub-boxes (admissible when one is).
  double sample_m = 0.02;
  /// Boxes the search may settle; more: undecided (a region that large is no pocket).
  std::size_t max_boxes = 200000;
  /// Wall clock the search may take [s]; when over: undecided. Absent: none.
  std::optional<double> time_limit_s;
};

/// Which paths the check follows from the pose.
enum class TrapDirection {
  kLeaving,   ///< paths that start at the pose (the start)
  kArriving,  ///< paths that end at the pose, followed backwards (the goal)
};

/// What the check found.
enum class TrapOutcome {
  kTrapped,       ///< no admissible path leaves the region searched: a proof
  kEscapes,       ///< some chain of boxes meets the window's edge (proves nothing)
  kReachesOther,  ///< some chain of boxes holds the other end's pose (proves nothing)
  kUndecided,     ///< max_boxes or the time limit ended the search first
};

/// The outcome of checkCurvatureTrap().
struct CurvatureTrap {
  TrapOutcome outcome = TrapOutcome::kUndecided;
  int level = 0;  ///< which of GoalReachabilityOptions::curvature decided (0: the first)
  std::size_t boxes_settled = 0;     ///< boxes taken from the queue
  std::size_t attitude_samples = 0;  ///< vehicle attitudes computed
  double radius_m = 0.0;  ///< farthest box settled from the pose [m] (trapped: the region's reach)
  double area_m2 = 0.0;   ///< area of the positions settled [m^2]
  double time_ms = 0.0;   ///< wall clock [ms]
};

/// Whether every admissible path leaving (or arriving at) `pose` [m, map-local, rad] stays
/// within a region of the window around it that does not hold `other` (the far end, when
/// given). `limits` gives kappa_max [1/m], pitch_max and roll_max [rad]. Never throws (except
/// std::bad_alloc); a pose off the map or options out of range: kUndecided with nothing
/// searched. Cost: the boxes of the region (a pocket of 1 m^2: about 10^5 boxes and as many
/// attitudes), or a short walk to the window's edge over open ground.
CurvatureTrap checkCurvatureTrap(const TerrainFollowingModel& vehicle,
                                 const terrain::ElevationMap& map, const VehicleLimits& limits,
                                 const PlanarPose& pose, TrapDirection direction,
                                 const std::optional<PlanarPose>& other,
                                 const CurvatureTrapOptions& options = {});

}  // namespace terratraj::models
