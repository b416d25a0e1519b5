#include "terratraj/models/curvature_trap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace terratraj::models {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr int kSubsteps = 4;  // cos / sin bounds per step check

// Axis-aligned interval hull of poses: position [m] and heading [rad] (not wrapped).
struct Hull {
  double x_lo, x_hi, y_lo, y_hi, heading_lo, heading_hi;
};

// Range of cos over [a, b].
void cosRange(double a, double b, double& lo, double& hi) {
  if (b - a >= kTwoPi) {
    lo = -1.0;
    hi = 1.0;
    return;
  }
  const double ca = std::cos(a), cb = std::cos(b);
  lo = std::min(ca, cb);
  hi = std::max(ca, cb);
  if (kTwoPi * std::ceil(a / kTwoPi) <= b) hi = 1.0;                 // a multiple of 2 pi inside
  if (kPi + kTwoPi * std::ceil((a - kPi) / kTwoPi) <= b) lo = -1.0;  // pi + 2 pi n inside
}

// The search: boxes of the window around the pose, tested and queued on first need.
class TrapSearch {
 public:
  TrapSearch(const TerrainFollowingModel& vehicle, const terrain::ElevationMap& map,
             const VehicleLimits& limits, const PlanarPose& pose, TrapDirection direction,
             const CurvatureTrapOptions& options)
      : vehicle_(vehicle),
        map_(map),
        options_(options),
        pose_(pose),
        sign_(direction == TrapDirection::kLeaving ? 1.0 : -1.0),
        pitch_max_(limits.pitch_max * (1.0 + options.limit_tolerance)),
        roll_max_(limits.roll_max * (1.0 + options.limit_tolerance)),
        h_(options.box_m),
        bin_(kTwoPi / options.heading_bins),
        n_(static_cast<int>(std::ceil(2.0 * options.window_m / options.box_m))),
        origin_x_(pose.x - 0.5 * n_ * options.box_m),
        origin_y_(pose.y - 0.5 * n_ * options.box_m) {
    flags_.reserve(4096);
    settled_position_.reserve(1024);
    const double pitch_bound = std::min(pitch_max_, 0.49 * kPi);
    kappa_ = limits.kappa_max / (std::cos(pitch_bound) * std::cos(pitch_bound));
  }

  TrapOutcome run(const std::optional<PlanarPose>& other,
                  std::chrono::steady_clock::time_point started, CurvatureTrap& out) {
    other_ = other;
    // The pose itself: a box of no extent.
    const Hull start{pose_.x, pose_.x, pose_.y, pose_.y, pose_.heading, pose_.heading};
    if (const std::optional<TrapOutcome> ended = expand(start)) return *ended;
    while (!queue_.empty()) {
      const Entry e = queue_.top();
      queue_.pop();
      const int k = static_cast<int>(e.index % static_cast<std::size_t>(options_.heading_bins));
      const std::size_t cell = e.index / static_cast<std::size_t>(options_.heading_bins);
      const int i = static_cast<int>(cell % static_cast<std::size_t>(n_));
      const int j = static_cast<int>(cell / static_cast<std::size_t>(n_));
      if (!admissible(i, j, k)) continue;  // tested when taken: most queued boxes never are
      ++out.boxes_settled;
      if (settled_position_.insert(cell).second) out.area_m2 += h_ * h_;
      out.radius_m = std::max(out.radius_m, e.radius);
      if (out.boxes_settled > options_.max_boxes) return TrapOutcome::kUndecided;
      if (options_.time_limit_s && out.boxes_settled % 256 == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() >
              *options_.time_limit_s) {
        return TrapOutcome::kUndecided;
      }
      const Hull box{origin_x_ + i * h_, origin_x_ + (i + 1) * h_,
                     origin_y_ + j * h_, origin_y_ + (j + 1) * h_,
                     k * bin_,           (k + 1) * bin_};
      if (const std::optional<TrapOutcome> ended = expand(box)) return *ended;
    }
    out.attitude_samples = samples_;
    return TrapOutcome::kTrapped;
  }

  std::size_t samples() const { return samples_; }

 private:
  enum Flag : std::uint8_t { kTested = 1, kAdmissible = 2, kQueued = 4 };
  struct Entry {
    double exit;    // distance to the window's edge or the other end [m]: the nearest first
    double radius;  // distance from the pose [m]
    std::size_t index;
  };
  struct Farther {
    bool operator()(const Entry& a, const Entry& b) const { return a.exit > b.exit; }
  };

  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(j) * n_ + static_cast<std::size_t>(i)) *
               static_cast<std::size_t>(options_.heading_bins) +
           static_cast<std::size_t>(k);
  }

  // One move from `from`: the hulls at the step checks; ends the search when the sweep meets
  // the window's edge or holds the other end.
  std::optional<TrapOutcome> expand(const Hull& from) {
    const int checks = options_.step_checks;
    const double ds = options_.step_m / (checks * kSubsteps);
    double dx_lo = 0.0, dx_hi = 0.0, dy_lo = 0.0, dy_hi = 0.0;
    Hull sweep = from;
    for (int m = 1; m <= checks; ++m) {
      for (int q = 1; q <= kSubsteps; ++q) {
        const double sigma = ((m - 1) * kSubsteps + q) * ds;
        double c_lo, c_hi, s_lo, s_hi;
        cosRange(from.heading_lo - kappa_ * sigma, from.heading_hi + kappa_ * sigma, c_lo, c_hi);
        cosRange(from.heading_lo - kappa_ * sigma - 0.5 * kPi,
                 from.heading_hi + kappa_ * sigma - 0.5 * kPi, s_lo, s_hi);
        dx_lo += ds * (sign_ > 0 ? c_lo : -c_hi);
        dx_hi += ds * (sign_ > 0 ? c_hi : -c_lo);
        dy_lo += ds * (sign_ > 0 ? s_lo : -s_hi);
        dy_hi += ds * (sign_ > 0 ? s_hi : -s_lo);
        sweep.x_lo = std::min(sweep.x_lo, from.x_lo + dx_lo);
        sweep.x_hi = std::max(sweep.x_hi, from.x_hi + dx_hi);
        sweep.y_lo = std::min(sweep.y_lo, from.y_lo + dy_lo);
        sweep.y_hi = std::max(sweep.y_hi, from.y_hi + dy_hi);
      }
      const double turn = kappa_ * m * options_.step_m / checks;
      hulls_[static_cast<std::size_t>(m - 1)] = {from.x_lo + dx_lo,      from.x_hi + dx_hi,
                                                 from.y_lo + dy_lo,      from.y_hi + dy_hi,
                                                 from.heading_lo - turn, from.heading_hi + turn};
    }
    sweep.heading_lo = from.heading_lo - kappa_ * options_.step_m;
    sweep.heading_hi = from.heading_hi + kappa_ * options_.step_m;
    const double edge = n_ * h_;
    if (sweep.x_lo < origin_x_ || sweep.y_lo < origin_y_ || sweep.x_hi > origin_x_ + edge ||
        sweep.y_hi > origin_y_ + edge) {
      return TrapOutcome::kEscapes;
    }
    if (other_ && holds(sweep, *other_)) return TrapOutcome::kReachesOther;
    for (int m = 0; m + 1 < checks; ++m) {
      if (!anyAdmissible(hulls_[static_cast<std::size_t>(m)], false)) return std::nullopt;
    }
    anyAdmissible(hulls_[static_cast<std::size_t>(checks - 1)], true);
    return std::nullopt;
  }

  static bool holds(const Hull& hull, const PlanarPose& p) {
    const double mid = 0.5 * (hull.heading_lo + hull.heading_hi);
    return p.x >= hull.x_lo && p.x <= hull.x_hi && p.y >= hull.y_lo && p.y <= hull.y_hi &&
           (hull.heading_hi - hull.heading_lo >= kTwoPi ||
            std::abs(std::remainder(p.heading - mid, kTwoPi)) <=
                0.5 * (hull.heading_hi - hull.heading_lo));
  }

  // Whether an admissible box meets `hull`; with `queue`, queues every box that meets it
  // instead (untested) and returns whether there was one.
  bool anyAdmissible(const Hull& hull, bool queue) {
    const int i0 = std::max(0, static_cast<int>(std::floor((hull.x_lo - origin_x_) / h_)));
    const int i1 = std::min(n_ - 1, static_cast<int>(std::floor((hull.x_hi - origin_x_) / h_)));
    const int j0 = std::max(0, static_cast<int>(std::floor((hull.y_lo - origin_y_) / h_)));
    const int j1 = std::min(n_ - 1, static_cast<int>(std::floor((hull.y_hi - origin_y_) / h_)));
    const int bins = options_.heading_bins;
    long k0 = static_cast<long>(std::floor(hull.heading_lo / bin_));
    long k1 = static_cast<long>(std::floor(hull.heading_hi / bin_));
    if (k1 - k0 >= bins) k1 = k0 + bins - 1;
    bool any = false;
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        for (long kk = k0; kk <= k1; ++kk) {
          const int k = static_cast<int>(((kk % bins) + bins) % bins);
          if (!queue) {
            if (admissible(i, j, k)) return true;
            continue;
          }
          any = true;
          std::uint8_t& f = flags_[index(i, j, k)];  // 0 when new
          if (f & kQueued) continue;
          f = static_cast<std::uint8_t>(f | kQueued);
          const double cx = origin_x_ + (i + 0.5) * h_ - pose_.x;
          const double cy = origin_y_ + (j + 0.5) * h_ - pose_.y;
          queue_.push({exitDistance(i, j), std::hypot(cx, cy), index(i, j, k)});
        }
      }
    }
    return any;
  }

  // How far the box (i, j) is from ending the search: the window's edge or the other end.
  double exitDistance(int i, int j) const {
    const double edge = std::min({i + 0.5, j + 0.5, n_ - i - 0.5, n_ - j - 0.5}) * h_;
    if (!other_) return edge;
    return std::min(edge, std::hypot(origin_x_ + (i + 0.5) * h_ - other_->x,
                                     origin_y_ + (j + 0.5) * h_ - other_->y));
  }

  bool admissible(int i, int j, int k) {
    std::uint8_t& f = flags_[index(i, j, k)];  // 0 when new
    if (!(f & kTested)) f = static_cast<std::uint8_t>(f | kTested | test(i, j, k));
    return (f & kAdmissible) != 0;
  }

  // kAdmissible unless no pose of the box can be within the limits.
  std::uint8_t test(int i, int j, int k) {
    const double x0 = origin_x_ + i * h_, y0 = origin_y_ + j * h_;
    bool all_closed = true;
    for (const double x : {x0, x0 + h_}) {
      for (const double y : {y0, y0 + h_}) {
        const std::optional<terrain::CellIndex> c = map_.geometry().cellAt({x, y});
        if (c && !map_.isLethal(*c) && !map_.isNoData(*c)) all_closed = false;
      }
    }
    if (all_closed) return 0;
    // The first-order bound over sub-boxes of at most sample_m a side.
    const int m = std::max(1, static_cast<int>(std::ceil(h_ / options_.sample_m - 1e-9)));
    const double sub = h_ / m;
    const Eigen::Vector3d half(0.5 * sub, 0.5 * sub, 0.5 * bin_);
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) {
        const PlanarPose centre{x0 + (a + 0.5) * sub, y0 + (b + 0.5) * sub, (k + 0.5) * bin_};
        workspace_.has_warm_start = false;
        ++samples_;
        AttitudeResult result;
        // No attitude at the centre says nothing about the rest of the sub-box.
        if (vehicle_.compute(centre, workspace_, result) != AttitudeStatus::kOk) return kAdmissible;
        const double roll_spread = result.jacobian.row(1).cwiseAbs().dot(half);
        const double pitch_spread = result.jacobian.row(2).cwiseAbs().dot(half);
        if (std::abs(result.attitude.roll) - roll_spread <= roll_max_ &&
            std::abs(result.attitude.pitch) - pitch_spread <= pitch_max_) {
          return kAdmissible;
        }
      }
    }
    return 0;
  }

  const TerrainFollowingModel& vehicle_;
  const terrain::ElevationMap& map_;
  const CurvatureTrapOptions& options_;
  PlanarPose pose_;
  double sign_;
  double pitch_max_, roll_max_, kappa_ = 0.0;
  double h_, bin_;
  int n_;
  double origin_x_, origin_y_;
  // Only the boxes touched are stored: over open ground the search meets the window's edge
  // after a few hundred boxes, in a pocket it settles its few thousands.
  std::unordered_map<std::size_t, std::uint8_t> flags_;
  std::unordered_set<std::size_t> settled_position_;
  std::vector<Hull> hulls_ = std::vector<Hull>(64);
  std::priority_queue<Entry, std::vector<Entry>, Farther> queue_;
  std::optional<PlanarPose> other_;
  AttitudeWorkspace workspace_;
  std::size_t samples_ = 0;
};

bool validOptions(const CurvatureTrapOptions& o) {
  return o.window_m > 0.0 && o.box_m > 0.0 && o.heading_bins >= 8 && o.step_m > 2.0 * o.box_m &&
         o.step_checks >= 1 && o.step_checks <= 64 && o.limit_tolerance >= 0.0 &&
         o.window_m / o.box_m <= 4096.0 && o.sample_m > 0.0;
}

}  // namespace

CurvatureTrap checkCurvatureTrap(const TerrainFollowingModel& vehicle,
                                 const terrain::ElevationMap& map, const VehicleLimits& limits,
                                 const PlanarPose& pose, TrapDirection direction,
                                 const std::optional<PlanarPose>& other,
                                 const CurvatureTrapOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  CurvatureTrap out;
  if (!validOptions(options) || !map.geometry().cellAt({pose.x, pose.y}) ||
      !(limits.kappa_max > 0.0)) {
    return out;
  }
  TrapSearch search(vehicle, map, limits, pose, direction, options);
  out.outcome = search.run(other, started, out);
  out.attitude_samples = search.samples();
  out.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return out;
}

}  // namespace terratraj::models
