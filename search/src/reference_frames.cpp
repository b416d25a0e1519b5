#include "terratraj/search/reference_frames.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace terratraj::search {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A centroid this close to the anchor defines no ray [m].
constexpr double kMinCentroidDistance = 1e-9;
// Frames shorter than this are dropped [m].
constexpr double kMinFrameLength = 1e-9;
// Bounding boxes and bucket membership are grown by this much [m], far more than the rounding
// of any coordinate on a map < 10^6 m, so that no test that could succeed is skipped.
constexpr double kMargin = 1e-6;
constexpr double kBucketSize = 2.0;            // [m]
constexpr std::int64_t kMaxBuckets = 1 << 20;  // the bucket size grows beyond this
constexpr int kMaxQueryBuckets = 4;            // more: test every frame's box instead
constexpr std::size_t kHitBufferSize = 8;      // crossings of one segment sorted on the stack

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// One cell visited by a ray a + t d, t >= 0, over [t_enter, t_exit].
struct RayCell {
  terrain::CellIndex cell;
  double t_enter = 0.0;
  double t_exit = 0.0;
};

// The cells of the map crossed by the ray a + t d (d a unit vector, t >= 0), in order, up to
// the map edge (exact grid traversal, Amanatides & Woo). Through a cell corner the ray visits
// one of the two side cells for zero length (x step first).
std::vector<RayCell> traverseRay(const terrain::GridGeometry& g, const Eigen::Vector2d& a,
                                 const Eigen::Vector2d& d) {
  std::vector<RayCell> cells;
  const double extent[2] = {g.width(), g.height()};
  double t_in = 0.0;
  double t_out = kInf;
  for (int i = 0; i < 2; ++i) {
    if (d[i] == 0.0) {
      if (a[i] < 0.0 || a[i] > extent[i]) return cells;
      continue;
    }
    const double t1 = (0.0 - a[i]) / d[i];
    const double t2 = (extent[i] - a[i]) / d[i];
    t_in = std::max(t_in, std::min(t1, t2));
    t_out = std::min(t_out, std::max(t1, t2));
  }
  if (!(t_in <= t_out)) return cells;

  // The first cell: on a cell border, the one the ray goes into.
  const Eigen::Vector2d p0 = a + t_in * d;
  const auto firstIndex = [&](double coordinate, double direction, int count) {
    const double scaled = coordinate / g.cell;
    const double index = direction < 0.0 ? std::ceil(scaled) - 1.0 : std::floor(scaled);
    return static_cast<int>(std::clamp(index, 0.0, static_cast<double>(count - 1)));
  };
  int col = firstIndex(p0.x(), d.x(), g.cols);
  int row = firstIndex(p0.y(), d.y(), g.rows);
  const int step_x = d.x() > 0.0 ? 1 : (d.x() < 0.0 ? -1 : 0);
  const int step_y = d.y() > 0.0 ? 1 : (d.y() < 0.0 ? -1 : 0);

  double t_enter = t_in;
  while (row >= 0 && row < g.rows && col >= 0 && col < g.cols) {
    const double tx = step_x > 0   ? ((col + 1) * g.cell - a.x()) / d.x()
                      : step_x < 0 ? (col * g.cell - a.x()) / d.x()
                                   : kInf;
    const double ty = step_y > 0   ? ((row + 1) * g.cell - a.y()) / d.y()
                      : step_y < 0 ? (row * g.cell - a.y()) / d.y()
                                   : kInf;
    const double t_exit = std::max(t_enter, std::min(tx, ty));
    cells.push_back({terrain::CellIndex{row, col}, t_enter, t_exit});
    if (tx <= ty) {
      col += step_x;
    } else {
      row += step_y;
    }
    t_enter = t_exit;
  }
  return cells;
}

// Membership of one cluster's cells: bounding box, then binary search.
class ClusterCells {
 public:
  ClusterCells(const terrain::GridGeometry& g, const terrain::ObstacleCluster& cluster)
      : geometry_(g) {
    indices_.reserve(cluster.cells.size());
    for (const terrain::CellIndex& c : cluster.cells) {
      if (!g.isValid(c)) continue;
      indices_.push_back(g.linearIndex(c));
      min_ = {std::min(min_.row, c.row), std::min(min_.col, c.col)};
      max_ = {std::max(max_.row, c.row), std::max(max_.col, c.col)};
    }
    std::sort(indices_.begin(), indices_.end());
  }
  bool contains(terrain::CellIndex c) const {
    if (c.row < min_.row || c.row > max_.row || c.col < min_.col || c.col > max_.col) {
      return false;
    }
    return std::binary_search(indices_.begin(), indices_.end(), geometry_.linearIndex(c));
  }

 private:
  const terrain::GridGeometry& geometry_;
  std::vector<std::size_t> indices_;
  terrain::CellIndex min_{std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  terrain::CellIndex max_{std::numeric_limits<int>::min(), std::numeric_limits<int>::min()};
};

// Distance from point x to segment [a, b].
double distanceToSegment(const Eigen::Vector2d& x, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double squared = ab.squaredNorm();
  const double t = squared > 0.0 ? std::clamp((x - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
  return (a + t * ab - x).norm();
}

}  // namespace

ReferenceFrames ReferenceFrames::build(const terrain::ElevationMap& map,
                                       const std::vector<terrain::ObstacleCluster>& clusters,
                                       const ReferenceFrameOptions& options) {
  ReferenceFrames result;
  result.anchor_ = options.anchor;
  const terrain::GridGeometry& g = map.geometry();
  if (!options.anchor.allFinite() || !std::isfinite(options.frame_radius) ||
      !(options.frame_radius > 0.0) || g.rows <= 0 || g.cols <= 0) {
    return result;
  }
  const Eigen::Vector2d& anchor = options.anchor;
  const std::optional<terrain::CellIndex> anchor_cell = g.cellAt(anchor);
  const terrain::GridLayer* lethal = map.findLayer(terrain::layer_names::kLethal);
  const terrain::GridLayer& elevation = map.elevation();
  const auto blocked = [&](terrain::CellIndex c) {
    if (std::isnan(elevation(c))) return true;
    if (lethal == nullptr) return false;
    const float value = (*lethal)(c);
    return value != 0.0f && !std::isnan(value);
  };

  for (std::size_t k = 0; k < clusters.size(); ++k) {
    const terrain::ObstacleCluster& cluster = clusters[k];
    if (cluster.cells.empty() || !g.cellAt(cluster.centroid)) continue;
    const Eigen::Vector2d offset = cluster.centroid - anchor;
    const double distance = offset.norm();
    if (distance <= kMinCentroidDistance || distance > options.frame_radius) continue;
    const ClusterCells members(g, cluster);
    if (anchor_cell && members.contains(*anchor_cell)) continue;

    const Eigen::Vector2d direction = offset / distance;
    const std::vector<RayCell> ray = traverseRay(g, anchor, direction);
    if (ray.empty()) continue;

    // Start: where the ray leaves the cluster's farthest cell; else the centroid.
    bool found = false;
    double t_start = distance;
    std::size_t next = 0;  // the first cell that may end the frame
    for (std::size_t i = ray.size(); i-- > 0;) {
      if (members.contains(ray[i].cell)) {
        found = true;
        t_start = ray[i].t_exit;
        next = i + 1;
        break;
      }
    }
    if (!found) {
      // From the cell holding the centroid (if it is blocked, the frame has no length).
      while (next < ray.size() && ray[next].t_exit <= distance) ++next;
    }
    // End: the next lethal or no-data cell, else the map edge.
    double t_end = ray.back().t_exit;
    for (std::size_t j = next; j < ray.size(); ++j) {
      if (blocked(ray[j].cell)) {
        t_end = std::max(t_start, ray[j].t_enter);
        break;
      }
    }
    if (!(t_end - t_start >= kMinFrameLength)) continue;

    ReferenceFrame frame;
    frame.cluster = static_cast<int>(k);
    frame.start = anchor + t_start * direction;
    frame.end = anchor + t_end * direction;
    // Rounding can leave the edge point a hair off the map.
    const Eigen::Vector2d extent(g.width(), g.height());
    frame.end = frame.end.cwiseMax(Eigen::Vector2d::Zero()).cwiseMin(extent);
    frame.start = frame.start.cwiseMax(Eigen::Vector2d::Zero()).cwiseMin(extent);
    const double length = frame.length();
    if (!(length >= kMinFrameLength)) continue;

    FrameGeometry geometry;
    geometry.start = frame.start;
    geometry.direction = (frame.end - frame.start) / length;
    geometry.length = length;
    geometry.box_min = frame.start.cwiseMin(frame.end).array() - kMargin;
    geometry.box_max = frame.start.cwiseMax(frame.end).array() + kMargin;
    result.frames_.push_back(frame);
    result.geometry_.push_back(geometry);
  }
  result.buildBuckets();
  return result;
}

void ReferenceFrames::buildBuckets() {
  bucket_offsets_.clear();
  bucket_frames_.clear();
  bucket_cols_ = bucket_rows_ = 0;
  if (geometry_.empty()) return;
  grid_min_ = geometry_.front().box_min;
  grid_max_ = geometry_.front().box_max;
  for (const FrameGeometry& f : geometry_) {
    grid_min_ = grid_min_.cwiseMin(f.box_min);
    grid_max_ = grid_max_.cwiseMax(f.box_max);
  }
  const Eigen::Vector2d extent = grid_max_ - grid_min_;
  bucket_size_ = kBucketSize;
  if ((extent.x() / bucket_size_ + 1.0) * (extent.y() / bucket_size_ + 1.0) >
      static_cast<double>(kMaxBuckets)) {
    bucket_size_ =
        std::sqrt(extent.x() * extent.y() / static_cast<double>(kMaxBuckets)) * 1.5 + kBucketSize;
  }
  inverse_bucket_size_ = 1.0 / bucket_size_;
  bucket_cols_ = std::max(1, static_cast<int>(std::ceil(extent.x() / bucket_size_)));
  bucket_rows_ = std::max(1, static_cast<int>(std::ceil(extent.y() / bucket_size_)));
  const std::size_t bucket_count = static_cast<std::size_t>(bucket_cols_) * bucket_rows_;

  // Frame f goes in every bucket its segment passes within kMargin of (a superset: distance
  // from the bucket centre <= half diagonal + margin).
  const double reach = bucket_size_ * std::sqrt(0.5) + kMargin;
  std::vector<std::vector<std::int32_t>> lists(bucket_count);
  for (std::size_t f = 0; f < geometry_.size(); ++f) {
    const FrameGeometry& frame = geometry_[f];
    const Eigen::Vector2d end = frame.start + frame.length * frame.direction;
    const auto index = [&](double value, double origin, int count) {
      const double i = std::floor((value - origin) * inverse_bucket_size_);
      return static_cast<int>(std::clamp(i, 0.0, static_cast<double>(count - 1)));
    };
    const int c0 = index(frame.box_min.x(), grid_min_.x(), bucket_cols_);
    const int c1 = index(frame.box_max.x(), grid_min_.x(), bucket_cols_);
    const int r0 = index(frame.box_min.y(), grid_min_.y(), bucket_rows_);
    const int r1 = index(frame.box_max.y(), grid_min_.y(), bucket_rows_);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const Eigen::Vector2d centre = grid_min_ + bucket_size_ * Eigen::Vector2d(c + 0.5, r + 0.5);
        if (distanceToSegment(centre, frame.start, end) <= reach) {
          lists[static_cast<std::size_t>(r) * bucket_cols_ + c].push_back(
              static_cast<std::int32_t>(f));
        }
      }
    }
  }
  bucket_offsets_.resize(bucket_count + 1);
  bucket_offsets_[0] = 0;
  for (std::size_t b = 0; b < bucket_count; ++b) {
    bucket_offsets_[b + 1] = bucket_offsets_[b] + static_cast<std::uint32_t>(lists[b].size());
    bucket_frames_.insert(bucket_frames_.end(), lists[b].begin(), lists[b].end());
  }
}

bool ReferenceFrames::crossing(int index, const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                               double& u, int& direction) const {
  const FrameGeometry& f = geometry_[static_cast<std::size_t>(index)];
  // Box test: a segment that misses the grown box cannot cross.
  if (std::max(p.x(), q.x()) < f.box_min.x() || std::min(p.x(), q.x()) > f.box_max.x() ||
      std::max(p.y(), q.y()) < f.box_min.y() || std::min(p.y(), q.y()) > f.box_max.y()) {
    return false;
  }
  const Eigen::Vector2d dp = p - f.start;
  const Eigen::Vector2d dq = q - f.start;
  const double side_p = cross(f.direction, dp);
  const double side_q = cross(f.direction, dq);
  const bool left_p = side_p >= 0.0;
  const bool left_q = side_q >= 0.0;
  if (left_p == left_q) return false;
  // The crossing's distance along the frame; a vertex on the frame's line gets exactly the
  // value it gets in the neighbouring segment of a polyline.
  const double along_p = f.direction.dot(dp);
  const double along_q = f.direction.dot(dq);
  double along;
  if (side_p == 0.0) {
    u = 0.0;
    along = along_p;
  } else if (side_q == 0.0) {
    u = 1.0;
    along = along_q;
  } else {
    u = side_p / (side_p - side_q);
    along = along_p + u * (along_q - along_p);
  }
  if (!(along >= 0.0 && along < f.length)) return false;
  direction = left_q ? +1 : -1;
  return true;
}

template <typename Visit>
void ReferenceFrames::forEachCandidate(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                                       Visit&& visit) const {
  // Precondition (appendCrossings): finite p and q, bounding box overlapping the grid.
  const Eigen::Vector2d lo = p.cwiseMin(q);
  const Eigen::Vector2d hi = p.cwiseMax(q);
  const auto index = [&](double value, double origin, int count) {
    const double i = std::floor((value - origin) * inverse_bucket_size_);
    return static_cast<int>(std::clamp(i, 0.0, static_cast<double>(count - 1)));
  };
  const int c0 = index(lo.x(), grid_min_.x(), bucket_cols_);
  const int c1 = index(hi.x(), grid_min_.x(), bucket_cols_);
  const int r0 = index(lo.y(), grid_min_.y(), bucket_rows_);
  const int r1 = index(hi.y(), grid_min_.y(), bucket_rows_);
  if ((c1 - c0 + 1) * (r1 - r0 + 1) > kMaxQueryBuckets) {
    for (std::size_t f = 0; f < geometry_.size(); ++f) visit(static_cast<int>(f));
    return;
  }
  const auto bucketBegin = [&](int r, int c) {
    return bucket_frames_.begin() + bucket_offsets_[static_cast<std::size_t>(r) * bucket_cols_ + c];
  };
  const auto bucketEnd = [&](int r, int c) {
    return bucket_frames_.begin() +
           bucket_offsets_[static_cast<std::size_t>(r) * bucket_cols_ + c + 1];
  };
  for (int r = r0; r <= r1; ++r) {
    for (int c = c0; c <= c1; ++c) {
      for (auto it = bucketBegin(r, c); it != bucketEnd(r, c); ++it) {
        // Each frame once: skip it if an earlier bucket of the range holds it.
        bool seen = false;
        for (int rr = r0; rr <= r && !seen; ++rr) {
          for (int cc = c0; cc <= c1; ++cc) {
            if (rr == r && cc == c) break;
            if (std::binary_search(bucketBegin(rr, cc), bucketEnd(rr, cc), *it)) {
              seen = true;
              break;
            }
          }
        }
        if (!seen) visit(*it);
      }
    }
  }
}

void ReferenceFrames::appendCrossings(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                                      HomotopySignature& signature) const {
  if (geometry_.empty()) return;
  // The common case first: a segment far from every frame. One branch (bitwise or: the four
  // comparisons are unpredictable for scattered segments). NaN passes and is caught next.
  const bool outside =
      (std::max(p.x(), q.x()) < grid_min_.x()) | (std::min(p.x(), q.x()) > grid_max_.x()) |
      (std::max(p.y(), q.y()) < grid_min_.y()) | (std::min(p.y(), q.y()) > grid_max_.y());
  if (outside) return;
  if (!std::isfinite(p.x() + p.y() + q.x() + q.y())) return;

  struct Hit {
    double u;
    int frame;
    int direction;
    bool operator<(const Hit& other) const {
      return u < other.u || (u == other.u && frame < other.frame);
    }
  };
  std::array<Hit, kHitBufferSize> hits;
  std::size_t count = 0;
  forEachCandidate(p, q, [&](int f) {
    Hit hit{0.0, f, 0};
    if (!crossing(f, p, q, hit.u, hit.direction)) return;
    if (count < hits.size()) hits[count] = hit;
    ++count;
  });
  if (count == 0) return;
  if (count <= hits.size()) {
    std::sort(hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(count));
    for (std::size_t i = 0; i < count; ++i) signature.append({hits[i].frame, hits[i].direction});
    return;
  }
  // More crossings than the buffer holds (a long segment through many frames): emit them in
  // order by repeated selection of the next smallest (u, frame). The tests are deterministic,
  // so every pass sees the same hits.
  Hit last{-kInf, -1, 0};
  for (std::size_t emitted = 0; emitted < count; ++emitted) {
    Hit best{kInf, std::numeric_limits<int>::max(), 0};
    forEachCandidate(p, q, [&](int f) {
      Hit hit{0.0, f, 0};
      if (!crossing(f, p, q, hit.u, hit.direction)) return;
      if (last < hit && hit < best) best = hit;
    });
    signature.append({best.frame, best.direction});
    last = best;
  }
}

HomotopySignature ReferenceFrames::signatureOf(const std::vector<Eigen::Vector2d>& polyline) const {
  HomotopySignature signature;
  for (std::size_t i = 1; i < polyline.size(); ++i) {
    appendCrossings(polyline[i - 1], polyline[i], signature);
  }
  return signature;
}

HomotopySignature ReferenceFrames::signatureBetween(const Eigen::Vector2d& start,
                                                    const std::vector<Eigen::Vector2d>& polyline,
                                                    const Eigen::Vector2d& goal) const {
  HomotopySignature signature;
  Eigen::Vector2d previous = start;
  for (const Eigen::Vector2d& point : polyline) {
    appendCrossings(previous, point, signature);
    previous = point;
  }
  appendCrossings(previous, goal, signature);
  return signature;
}

}  // namespace terratraj::search
