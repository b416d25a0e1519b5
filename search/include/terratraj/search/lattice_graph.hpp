#pragma once
// LatticeGraph: the state lattice on a map (the problem side of the lattice searches, as an
// OMPL state space is to its planners): states, edges replayed from motion primitives, edge
// validity and cost on the terrain, the heuristic, the goal test and the trajectory of a path.
//
// States are (i, j, k): position start + resolution * (i, j), heading index k (the lattice is
// anchored at the start position). When the start heading is not a lattice heading, the start
// is a state of its own whose edges are connectors: primitives solved at construction from the
// exact start heading to the end states of the nearest heading's primitives.
//
// Edge validity (002_..., 003_...): every map cell the primitive's curve passes through (within
// cell / 16) is on
// the map, neither lethal nor no data; at every search sample (every `sample_spacing` metres)
// the vehicle's attitude model rests on the terrain with |pitch| <= pitch_max and |roll| <=
// roll_max. Edge cost: the time to drive the edge at the speed caps (003_...): v_max,
// omega_max / |kappa|, sigma_max / |d kappa / ds|, the pitch table and the roll x curvature
// table, v^2 linear between samples (acceleration ignored, so the cost is a lower bound of the
// driven time), each segment's time weighted by 1 + alpha (roll^2 + pitch^2) (slope dwell,
// 004_... eq. 17). The heuristic (distance to the goal region) / v_max is admissible.
//
// Not thread-safe: evaluation uses the graph's own attitude workspace.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/search/motion_primitive.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/speed_profile.hpp"
#include "terratraj/terrain/expected.hpp"

namespace terratraj::search {

/// A lattice state. heading == kStartHeading marks the exact start when its heading is not a
/// lattice heading.
struct LatticeState {
  int i = 0;
  int j = 0;
  int heading = 0;
  bool operator==(const LatticeState& o) const {
    return i == o.i && j == o.j && heading == o.heading;
  }
};

/// Heading index of the off-lattice start state.
inline constexpr int kStartHeading = -1;

/// Why an edge is invalid.
enum class EdgeStatus {
  kValid,
  kOffMap,    ///< leaves the map or the lattice
  kLethal,    ///< passes through a lethal or no-data cell
  kAttitude,  ///< the vehicle cannot rest on the terrain somewhere along it
  kPitch,     ///< |pitch| > pitch_max
  kRoll,      ///< |roll| > roll_max
  kStall,     ///< a speed cap is below kMinCapSpeed (a table bin holding 0, say)
};

/// "valid", "off_map", "lethal", "attitude", "pitch", "roll", "stall".
const char* edgeStatusName(EdgeStatus status);

/// The outcome of one edge evaluation.
struct EdgeEvaluation {
  EdgeStatus status = EdgeStatus::kValid;
  double cost = 0.0;  ///< [s] (time, or slope-dwell weighted time)
  double time = 0.0;  ///< at the speed caps [s]
};

/// Settings of the graph.
struct LatticeGraphOptions {
  /// Spacing of the attitude / speed samples along edges [m]; <= 0: half the map cell.
  double sample_spacing = 0.0;
  double slope_dwell_alpha = 0.0;  ///< alpha of the slope-dwell cost [1/rad^2], >= 0
};

/// One step of a path: the state it leaves and the edge taken.
struct LatticeStep {
  LatticeState from;
  int edge = 0;
};

/// A path turned into a trajectory.
struct LatticeTrajectory {
  models::Trajectory trajectory;  ///< every contract column filled
  double duration = 0.0;          ///< with the bang-bang speed profile [s]
  double length = 0.0;            ///< planar length [m]
  double cost = 0.0;              ///< the search's cost of the path [s]
};

/// The lattice of one planning problem.
class LatticeGraph {
 public:
  /// `problem` and `primitives` must outlive the graph. Construction never throws; check
  /// error() before use.
  LatticeGraph(const PlanningProblem& problem, const PrimitiveSet& primitives,
               const LatticeGraphOptions& options = {});

  /// Why the graph cannot be searched (a message naming what is at fault: the primitives, the
  /// resolution, the start's curvature, no connector from the start heading), or std::nullopt.
  const std::optional<std::string>& error() const { return error_; }

  const PlanningProblem& problem() const { return *problem_; }
  const LatticeSpec& lattice() const { return primitives_->lattice; }
  const PrimitiveSet& primitives() const { return *primitives_; }

  /// The start state.
  LatticeState start() const { return start_; }
  /// A unique key (< 2^42) for a state on the lattice's extent.
  std::uint64_t key(const LatticeState& s) const;
  /// Whether a state's position lies on the lattice's extent (over the map).
  bool onLattice(const LatticeState& s) const;
  /// Position of a state [m, local].
  Eigen::Vector2d position(const LatticeState& s) const;
  /// Heading of a state [rad].
  double heading(const LatticeState& s) const;
  /// Whether a state lies in the goal region (position and heading; the speed profile brakes
  /// to the goal's speed).
  bool inGoal(const LatticeState& s) const;
  /// Admissible estimate of the cost to the goal region [s].
  double heuristic(const LatticeState& s) const;

  /// Number of edges leaving `s`.
  int edgeCount(const LatticeState& s) const;
  /// The primitive of edge `e` of `s`.
  const MotionPrimitive& primitive(const LatticeState& s, int e) const;
  /// The state edge `e` of `s` ends in (may be off the lattice: onLattice()).
  LatticeState target(const LatticeState& s, int e) const;
  /// Validity and cost of edge `e` of `s`. A pure function of (s, e).
  EdgeEvaluation evaluate(const LatticeState& s, int e) const;
  /// Positions of the search samples of edge `e` of `s` [m, local], first = s, last = target.
  void edgePoints(const LatticeState& s, int e, std::vector<Eigen::Vector2d>& out) const;

  /// The trajectory of a path from the start: samples every sample_spacing, attitude from the
  /// vehicle model, the bang-bang speed profile (001_... IV.C) from the start's speed to the
  /// goal's under the caps. A failure with the reason when a step is invalid or no profile
  /// exists (the start too fast for the first caps, too short to brake).
  Expected<LatticeTrajectory> trajectory(const std::vector<LatticeStep>& path) const;

  /// Number of start connectors (0 when the start heading is a lattice heading).
  std::size_t connectorCount() const { return connectors_.size(); }
  /// The spacing of the search samples [m].
  double sampleSpacing() const { return sample_spacing_; }

 private:
  struct SearchSample {
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // from the start node [m]
    double heading = 0.0;
    double curvature = 0.0;
    double rate_cap = 0.0;  // sigma_max / max |d kappa / ds| around the sample (or v_max)
    double ds = 0.0;        // planar distance from the previous sample [m] (0 for the first)
  };
  struct EdgeTemplate {
    std::vector<SearchSample> samples;
    std::vector<Eigen::Vector2i> cells;  // footprint (col, row) offsets (integer mode)
    std::vector<Eigen::Vector2d> dense;  // dense curve points (fallback mode)
  };
  EdgeTemplate makeTemplate(const MotionPrimitive& p) const;
  const EdgeTemplate& edgeTemplate(const LatticeState& s, int e) const;
  // Speed cap at a sample with the given attitude.
  double cap(const SearchSample& sample, double pitch, double roll) const;

  const PlanningProblem* problem_;
  const PrimitiveSet* primitives_;
  LatticeGraphOptions options_;
  std::optional<std::string> error_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  LatticeState start_;
  double sample_spacing_ = 0.125;
  int cells_per_node_ = 0;  // resolution / cell when an integer, else 0 (fallback)
  int i_min_ = 0, i_max_ = 0, j_min_ = 0, j_max_ = 0;
  std::vector<std::vector<EdgeTemplate>> templates_;  // by heading, as the primitives
  std::vector<MotionPrimitive> connectors_;
  std::vector<EdgeTemplate> connector_templates_;
  mutable models::AttitudeWorkspace workspace_;
  mutable models::AttitudeResult attitude_;
  mutable SpeedProfile profile_;
};

}  // namespace terratraj::search
