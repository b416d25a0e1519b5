#include "terratraj/models/goal_reachability.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <queue>
#include <sstream>
#include <vector>

namespace terratraj::models {
namespace {

constexpr double kPi = 3.14159265358979323846;

// What a cell is, once tested.
enum class CellKind : std::uint8_t {
  kUnknown,
  kPassable,
  kSteep,      // no sample rests within the pitch and roll limits
  kNoContact,  // no sample has an attitude (off the terrain, no contact)
  kLethal,
  kNoData,
};

// The search's state space: (cell, heading sector), each tested on first need.
class StateTester {
 public:
  StateTester(const TerrainFollowingModel& vehicle, const terrain::ElevationMap& map,
              const VehicleLimits& limits, const GoalReachabilityOptions& options)
      : vehicle_(vehicle),
        map_(map),
        pitch_max_(limits.pitch_max * (1.0 + options.limit_tolerance)),
        roll_max_(limits.roll_max * (1.0 + options.limit_tolerance)),
        sectors_(std::max(4, options.sectors)),
        kinds_(map.geometry().cellCount() * static_cast<std::size_t>(sectors_),
               CellKind::kUnknown) {}

  int sectors() const { return sectors_; }
  double width() const { return 2.0 * kPi / sectors_; }
  double middle(int sector) const { return width() * sector; }
  std::size_t index(terrain::CellIndex c, int sector) const {
    return map_.geometry().linearIndex(c) * static_cast<std::size_t>(sectors_) +
           static_cast<std::size_t>(sector);
  }
  CellKind kind(terrain::CellIndex c, int sector) {
    CellKind& k = kinds_[index(c, sector)];
    if (k == CellKind::kUnknown) k = test(c, sector);
    return k;
  }
  void markOpen(terrain::CellIndex c, int sector) {
    kinds_[index(c, sector)] = CellKind::kPassable;
  }
  std::size_t samples() const { return samples_; }
  /// The cell's kind for any heading: passable when one sector is, else the first sector's.
  CellKind anySector(terrain::CellIndex c) {
    const CellKind first = kind(c, 0);
    if (first == CellKind::kPassable || first == CellKind::kLethal || first == CellKind::kNoData) {
      return first;
    }
    for (int k = 1; k < sectors_; ++k) {
      if (kind(c, k) == CellKind::kPassable) return CellKind::kPassable;
    }
    return first;
  }

 private:
  CellKind test(terrain::CellIndex c, int sector) {
    if (map_.isNoData(c)) return CellKind::kNoData;
    if (map_.isLethal(c)) return CellKind::kLethal;
    const terrain::GridGeometry& g = map_.geometry();
    const Eigen::Vector2d centre = g.cellCenter(c);
    const double h = 0.5 * g.cell;
    const std::array<Eigen::Vector2d, 5> points = {
        centre, centre + Eigen::Vector2d(-h, -h), centre + Eigen::Vector2d(h, -h),
        centre + Eigen::Vector2d(-h, h), centre + Eigen::Vector2d(h, h)};
    bool any_attitude = false;
    for (const Eigen::Vector2d& p : points) {
      for (const double offset : {0.0, -0.5, 0.5, -0.25, 0.25}) {
        const double heading = middle(sector) + offset * width();
        AttitudeResult result;
        workspace_.has_warm_start = false;
        ++samples_;
        if (vehicle_.compute({p.x(), p.y(), heading}, workspace_, result) != AttitudeStatus::kOk) {
          continue;
        }
        any_attitude = true;
        if (std::abs(result.attitude.pitch) <= pitch_max_ &&
            std::abs(result.attitude.roll) <= roll_max_) {
          return CellKind::kPassable;
        }
      }
    }
    return any_attitude ? CellKind::kSteep : CellKind::kNoContact;
  }

  const TerrainFollowingModel& vehicle_;
  const terrain::ElevationMap& map_;
  double pitch_max_, roll_max_;
  int sectors_;
  std::vector<CellKind> kinds_;
  AttitudeWorkspace workspace_;
  std::size_t samples_ = 0;
};

// The sectors whose closed range holds `heading` (within 0.01 rad): one, or two at an edge.
std::vector<int> sectorsHolding(double heading, const StateTester& states) {
  std::vector<int> out;
  for (int k = 0; k < states.sectors(); ++k) {
    if (std::abs(std::remainder(heading - states.middle(k), 2.0 * kPi)) <=
        0.5 * states.width() + 0.01) {
      out.push_back(k);
    }
  }
  return out;
}

// Whether a heading of `sector` can cross from a cell into its neighbour (dr, dc): a positive
// component along dc (x) when dc != 0 and along dr (y) when dr != 0, for some heading of the
// closed sector.
bool crosses(const StateTester& states, int sector, int dr, int dc) {
  const double direction = std::atan2(static_cast<double>(dr), static_cast<double>(dc));
  const double half_cone = (dr != 0 && dc != 0) ? 0.25 * kPi : 0.5 * kPi;
  return std::abs(std::remainder(states.middle(sector) - direction, 2.0 * kPi)) <
         half_cone + 0.5 * states.width();
}

// One best-first search from the start towards the goal, greedy on the distance to the goal
// (over open terrain it walks nearly straight there). By sector: the relaxation of the file
// comment. By cell (`by_cell`): a cell is open when any sector of it is, every neighbour can be
// entered and headings are ignored: weaker (it proves less), but a region of N cells costs N
// states instead of up to 16 N, so it settles a goal boxed in by lethal cells on a whole map
// first.
class ReachabilitySearch {
 public:
  ReachabilitySearch(StateTester& states, const terrain::GridGeometry& g, const PlanarPose& start,
                     const PlanarPose& goal, terrain::CellIndex from, terrain::CellIndex to)
      : states_(states),
        g_(g),
        from_(from),
        to_(to),
        start_sectors_(sectorsHolding(start.heading, states)),
        goal_sectors_(sectorsHolding(goal.heading, states)) {
    for (int k : start_sectors_) states_.markOpen(from_, k);
    for (int k : goal_sectors_) states_.markOpen(to_, k);
  }

  enum class Outcome { kReached, kExhausted, kOutOfTime };

  Outcome run(bool by_cell, const std::optional<double>& time_limit_s,
              std::chrono::steady_clock::time_point started, GoalReachability& out) {
    by_cell_ = by_cell;
    const int n = by_cell ? 1 : states_.sectors();
    queued_.assign(g_.cellCount() * static_cast<std::size_t>(n), false);
    std::vector<bool> reached(g_.cellCount(), false);
    queue_ = {};
    borders_.fill(0);
    off_map_ = 0;
    out.cells_reached = 0;
    if (by_cell) {
      push(from_, 0);
    } else {
      for (int k : start_sectors_) push(from_, k);
    }
    while (!queue_.empty()) {
      const Entry e = queue_.top();
      queue_.pop();
      ++out.states_visited;
      if (!reached[g_.linearIndex(e.cell)]) {
        reached[g_.linearIndex(e.cell)] = true;
        ++out.cells_reached;
      }
      if (e.cell == to_ && (by_cell || std::find(goal_sectors_.begin(), goal_sectors_.end(),
                                                 e.sector) != goal_sectors_.end())) {
        return Outcome::kReached;
      }
      if (time_limit_s && out.states_visited % 256 == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >
              *time_limit_s) {
        return Outcome::kOutOfTime;
      }
      if (!by_cell) {  // turn into the next sector inside the cell
        consider(e.cell, (e.sector + 1) % n);
        consider(e.cell, (e.sector + n - 1) % n);
      }
      // Drive across an edge or a corner (by sector: one the sector's headings cross).
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr == 0 && dc == 0) || (!by_cell && !crosses(states_, e.sector, dr, dc))) continue;
          const terrain::CellIndex next{e.cell.row + dr, e.cell.col + dc};
          if (!g_.isValid(next)) {
            ++off_map_;
            continue;
          }
          consider(next, e.sector);
        }
      }
    }
    return Outcome::kExhausted;
  }

  /// What refused the last run's states, by CellKind; and moves off the map.
  const std::array<std::size_t, 6>& borders() const { return borders_; }
  std::size_t offMap() const { return off_map_; }

 private:
  struct Entry {
    double priority;
    terrain::CellIndex cell;
    int sector;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const { return a.priority > b.priority; }
  };

  std::size_t slot(terrain::CellIndex c, int k) const {
    return by_cell_ ? g_.linearIndex(c) : states_.index(c, k);
  }
  void push(terrain::CellIndex c, int k) {
    queued_[slot(c, k)] = true;
    queue_.push(
        {std::hypot(static_cast<double>(c.row - to_.row), static_cast<double>(c.col - to_.col)), c,
         k});
  }
  void consider(terrain::CellIndex c, int k) {
    if (queued_[slot(c, k)]) return;
    const CellKind kind = by_cell_ ? states_.anySector(c) : states_.kind(c, k);
    if (kind != CellKind::kPassable) {
      ++borders_[static_cast<std::size_t>(kind)];
      return;
    }
    push(c, k);
  }

  StateTester& states_;
  const terrain::GridGeometry& g_;
  terrain::CellIndex from_, to_;
  std::vector<int> start_sectors_, goal_sectors_;
  bool by_cell_ = false;
  std::vector<bool> queued_;
  std::priority_queue<Entry, std::vector<Entry>, Later> queue_;
  std::array<std::size_t, 6> borders_{};
  std::size_t off_map_ = 0;
};

// `value` to three significant digits, for a reason.
std::string threeDigits(double value) {
  std::ostringstream text;
  text.precision(3);
  text << value;
  return text.str();
}

// The curvature checks (curvature_trap.hpp) at the goal, then at the start; true when one proved
// the goal unreachable (`out` then says why).
// One end: the levels in turn until one proves a trap; the counts and times summed.
CurvatureTrap trapAt(const TerrainFollowingModel& vehicle, const terrain::ElevationMap& map,
                     const VehicleLimits& limits, const PlanarPose& pose, TrapDirection direction,
                     const PlanarPose& other, const GoalReachabilityOptions& options,
                     std::chrono::steady_clock::time_point started) {
  CurvatureTrap total;
  for (std::size_t level = 0; level < options.curvature.size(); ++level) {
    CurvatureTrapOptions trap = options.curvature[level];
    if (options.time_limit_s) {
      const double spent =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      const double left = std::max(0.0, *options.time_limit_s - spent);
      trap.time_limit_s = std::min(trap.time_limit_s.value_or(left), left);
    }
    const CurvatureTrap t = checkCurvatureTrap(vehicle, map, limits, pose, direction, other, trap);
    total.outcome = t.outcome;
    total.level = static_cast<int>(level);
    total.boxes_settled += t.boxes_settled;
    total.attitude_samples += t.attitude_samples;
    total.radius_m = t.radius_m;
    total.area_m2 = t.area_m2;
    total.time_ms += t.time_ms;
    if (t.outcome == TrapOutcome::kTrapped) break;
  }
  return total;
}

bool checkCurvatureAtTheEnds(const TerrainFollowingModel& vehicle, const terrain::ElevationMap& map,
                             const VehicleLimits& limits, const PlanarPose& start,
                             const PlanarPose& goal, const GoalReachabilityOptions& options,
                             std::chrono::steady_clock::time_point started, GoalReachability& out) {
  out.goal_trap =
      trapAt(vehicle, map, limits, goal, TrapDirection::kArriving, start, options, started);
  const CurvatureTrap* proof = nullptr;
  const char* end = nullptr;
  const char* other = nullptr;
  if (out.goal_trap->outcome == TrapOutcome::kTrapped) {
    proof = &*out.goal_trap;
    end = "arrive at the goal's pose";
    other = "from poses";
  } else {
    out.start_trap =
        trapAt(vehicle, map, limits, start, TrapDirection::kLeaving, goal, options, started);
    if (out.start_trap->outcome == TrapOutcome::kTrapped) {
      proof = &*out.start_trap;
      end = "leave the start's pose";
      other = "for poses";
    }
  }
  if (proof == nullptr) return false;
  out.reachable = false;
  std::ostringstream why;
  why.precision(3);
  why << "the goal cannot be reached from the start: driving forwards with curvature at most "
      << limits.kappa_max << " 1/m, the vehicle can " << end;
  if (proof->boxes_settled == 0) {
    why << " only over the first "
        << options.curvature[static_cast<std::size_t>(proof->level)].step_m << " m";
  } else {
    why << " only " << other << " within " << proof->radius_m << " m of it (" << proof->area_m2
        << " m^2 of positions)";
  }
  why << ", boxed in by slopes where pitch exceeds " << limits.pitch_max * 180.0 / kPi
      << " deg or roll " << limits.roll_max * 180.0 / kPi << " deg ("
      << options.curvature[static_cast<std::size_t>(proof->level)].limit_tolerance * 100.0
      << " % slack) or by impassable cells; the other end is not among them";
  out.reason = why.str();
  out.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return true;
}

}  // namespace

std::vector<CurvatureTrapOptions> defaultCurvatureLevels() {
  CurvatureTrapOptions coarse;
  coarse.box_m = 0.02;
  coarse.heading_bins = 180;
  coarse.step_m = 0.15;
  return {coarse, CurvatureTrapOptions{}};
}

GoalReachability checkGoalReachability(const TerrainFollowingModel& vehicle,
                                       const terrain::ElevationMap& map,
                                       const VehicleLimits& limits, const PlanarPose& start,
                                       const PlanarPose& goal,
                                       const GoalReachabilityOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  GoalReachability out;
  const terrain::GridGeometry& g = map.geometry();
  const std::optional<terrain::CellIndex> from = g.cellAt({start.x, start.y});
  const std::optional<terrain::CellIndex> to = g.cellAt({goal.x, goal.y});
  if (!from || !to) return out;
  StateTester states(vehicle, map, limits, options);
  ReachabilitySearch search(states, g, start, goal, *from, *to);
  // By cell first (cheap, proves a boxed-in goal), then by sector (proves more).
  ReachabilitySearch::Outcome outcome = ReachabilitySearch::Outcome::kReached;
  for (const bool by_cell : {true, false}) {
    outcome = search.run(by_cell, options.time_limit_s, started, out);
    if (outcome != ReachabilitySearch::Outcome::kReached) break;
  }
  out.attitude_samples = states.samples();
  out.decided = outcome != ReachabilitySearch::Outcome::kOutOfTime;
  out.reachable = outcome != ReachabilitySearch::Outcome::kExhausted;
  if (outcome == ReachabilitySearch::Outcome::kReached && !options.curvature.empty() &&
      checkCurvatureAtTheEnds(vehicle, map, limits, start, goal, options, started, out)) {
    return out;
  }
  if (out.reachable) {
    out.time_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
            .count();
    return out;
  }
  std::ostringstream why;
  why.precision(3);
  why << "the goal cannot be reached from the start: driving forwards, the vehicle can reach "
      << out.cells_reached << " cells (" << out.cells_reached * g.cell * g.cell
      << " m^2) from the start, bounded by";
  const char* sep = " ";
  const auto border = [&](CellKind kind, const std::string& text) {
    if (search.borders()[static_cast<std::size_t>(kind)] == 0) return;
    why << sep << text;
    sep = ", ";
  };
  border(CellKind::kSteep, "slopes where no heading the vehicle can turn to keeps pitch within " +
                               threeDigits(limits.pitch_max * 180.0 / kPi) +
                               " deg and roll within " +
                               threeDigits(limits.roll_max * 180.0 / kPi) + " deg (" +
                               threeDigits(options.limit_tolerance * 100.0) + " % slack)");
  border(CellKind::kNoContact, "cells where the vehicle has no attitude (no contact)");
  border(CellKind::kLethal, "lethal cells");
  border(CellKind::kNoData, "no-data cells");
  if (search.offMap() > 0) why << sep << "the map's edge";
  out.reason = why.str();
  out.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return out;
}

}  // namespace terratraj::models
