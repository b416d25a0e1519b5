#pragma once
// DubinsPath: the shortest paths of bounded curvature between two poses (Dubins 1957; the six
// words LSL, RSR, LSR, RSL, RLR, LRL in the closed form of Shkel & Lumelsky 2001). They are the
// global seeds of the optimal-control core (refine::SeededSolver): at constant speed on flat
// ground the shortest of them is the minimum-time path, and elsewhere their shapes start the
// optimiser in the right place, where a local heuristic can start it in a loop.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace terratraj::ocp {

/// The six words: L = left arc, R = right arc, S = straight.
enum class DubinsWord { kLSL, kRSR, kLSR, kRSL, kRLR, kLRL };

/// "LSL", "RSR", ...
const char* dubinsWordName(DubinsWord word);

/// A pose of the plane: position [m] and heading [rad].
struct PlanePose {
  double x = 0.0, y = 0.0, heading = 0.0;
};

/// One point of a sampled path.
struct PathPoint2 {
  double s = 0.0;           ///< arc length from the start [m]
  double x = 0.0, y = 0.0;  ///< [m]
  double heading = 0.0;     ///< [rad], continuous along the path
  double curvature = 0.0;   ///< [1/m]
};

/// One Dubins path: a word and the lengths of its three segments.
struct DubinsPath {
  PlanePose start;
  DubinsWord word = DubinsWord::kLSL;
  double radius = 1.0;                        ///< turning radius [m], > 0
  std::array<double, 3> lengths = {0, 0, 0};  ///< of the three segments [m], >= 0

  double length() const { return lengths[0] + lengths[1] + lengths[2]; }
  /// The pose at arc length s [m] (clamped to [0, length()]).
  PathPoint2 at(double s) const;
  /// Points every `spacing` m at most (> 0), both ends included.
  std::vector<PathPoint2> sample(double spacing) const;
};

/// Every feasible word from `from` to `to` with turning radius `radius` (> 0), shortest first.
/// Words whose length differs from a shorter one's by less than 1e-9 m and that end at the same
/// path are kept: callers choose how many to try.
std::vector<DubinsPath> dubinsPaths(const PlanePose& from, const PlanePose& to, double radius);

}  // namespace terratraj::ocp
