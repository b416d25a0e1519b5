#pragma once
// ReferenceFrames: the line segments that cut the map into homotopy classes for the
// topology-aware lattice (TAEASL, 002_... II; construction and rules in docs/homotopy.md).
//
// Each obstacle cluster near an anchor (the map centre or the robot) gets one frame on the ray
// from the anchor through the cluster's centroid: from the far side of the cluster to the next
// impassable cell or the map edge. A path's HomotopySignature is the reduced word of the frames
// it crosses; paths that pass an obstacle on different sides get different words.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "terratraj/search/homotopy_signature.hpp"
#include "terratraj/terrain/elevation_map.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace terratraj::search {

/// One reference frame: a segment in the local map frame [m], oriented away from the anchor.
/// Its left side is the side reached by turning counter-clockwise from its direction.
struct ReferenceFrame {
  int cluster = 0;                                  ///< index of its cluster in build()'s input
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  ///< far side of the cluster [m, local]
  Eigen::Vector2d end = Eigen::Vector2d::Zero();    ///< next impassable cell or map edge [m]
  /// |end - start| [m]; always > 0 for a frame built by ReferenceFrames::build().
  double length() const { return (end - start).norm(); }
};

/// How to place the frames.
struct ReferenceFrameOptions {
  /// The frames' common centre (map centre or robot position) [m, local]. May lie off the map.
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();
  /// Only clusters whose centroid lies within this distance of the anchor get a frame
  /// (the paper's frame_radius) [m], > 0.
  double frame_radius = 10.0;
};

/// The reference frames of one map and anchor, with a bucket grid for fast crossing tests.
/// Immutable once built: every const member may be called from several threads at once.
class ReferenceFrames {
 public:
  /// No frames: every path has the empty signature.
  ReferenceFrames() = default;

  /// Builds one frame per cluster of `clusters` (findObstacleClusters(map), or any clusters of
  /// that map) whose centroid lies within options.frame_radius of options.anchor, in cluster
  /// order; frame i is named HomotopySignature::frameName(i). On the ray from the anchor
  /// through the centroid, a frame starts where the ray leaves the cluster's last cell (the
  /// farthest from the anchor; the centroid itself if the ray meets none of its cells) and ends
  /// where the ray enters the next lethal or no-data cell of the map, or at the map edge.
  /// No frame (the cluster is skipped; later frames keep consecutive indices) for a cluster
  /// that: has no cells or a centroid off the map; has its centroid within 1e-9 m of the
  /// anchor; contains the anchor's cell; or would get a frame shorter than 1e-9 m (it touches
  /// the map edge or a no-data cell on its far side: nothing can pass there anyway).
  /// A non-finite anchor, or a frame_radius that is not a positive finite number, gives no
  /// frames. Cost: one grid traversal per frame plus the bucket grid (2 m buckets).
  static ReferenceFrames build(const terrain::ElevationMap& map,
                               const std::vector<terrain::ObstacleCluster>& clusters,
                               const ReferenceFrameOptions& options);

  /// Whether there are no frames.
  bool empty() const { return frames_.empty(); }
  /// Number of frames.
  std::size_t size() const { return frames_.size(); }
  /// The frames; index = frame number in FrameCrossing::frame.
  const std::vector<ReferenceFrame>& frames() const { return frames_; }
  /// The anchor they were built for [m, local].
  const Eigen::Vector2d& anchor() const { return anchor_; }

  /// Appends to `signature` every crossing of the segment p -> q [m, local] with a frame, in
  /// order along p -> q (ties by frame index). Direction +1 when the motion goes from the
  /// frame's right to its left (cross(frame direction, q - p) > 0: counter-clockwise about the
  /// anchor), -1 otherwise. Half-open rules, so that a polyline is counted consistently: a point
  /// is on a frame's left when cross(frame direction, point - start) >= 0 (points on the
  /// frame's line count as left), and the segment crosses when p and q are on different sides
  /// and the crossing point lies at a distance in [0, length) from the frame's start. So a
  /// polyline vertex exactly on a frame counts once, and touching a frame and going back adds
  /// nothing or a pair that cancels. A segment with a non-finite coordinate adds nothing.
  /// No allocation except the signature's own growth; a segment far from every frame costs a
  /// few comparisons (bucket grid); segments spanning more than 2 x 2 buckets (> 2 m) test
  /// every frame's bounding box instead.
  void appendCrossings(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                       HomotopySignature& signature) const;

  /// The signature of a polyline (appendCrossings over its consecutive vertex pairs); empty for
  /// fewer than two vertices.
  HomotopySignature signatureOf(const std::vector<Eigen::Vector2d>& polyline) const;

  /// The signature of a path from `start` to `goal` [m, local] along `polyline`: the polyline
  /// closed by the segments start -> its first vertex and its last vertex -> goal. Use it to
  /// compare the classes of paths between the same two points that end near, not at, them (a
  /// planner's goal region, a solver's tolerance): a frame that passes between a path's end and
  /// the goal, or through the goal itself, then counts the same for every path. (An end point
  /// exactly on a frame's line is on its left, by the half-open rules: a path that stops a hair
  /// to the right of it would otherwise differ by one crossing from one that stops on it.)
  /// An empty polyline gives the signature of the segment start -> goal.
  HomotopySignature signatureBetween(const Eigen::Vector2d& start,
                                     const std::vector<Eigen::Vector2d>& polyline,
                                     const Eigen::Vector2d& goal) const;

 private:
  // A frame in the form the crossing test needs.
  struct FrameGeometry {
    Eigen::Vector2d start;
    Eigen::Vector2d direction;  // unit
    double length = 0.0;
    Eigen::Vector2d box_min;  // bounding box, grown by a small margin
    Eigen::Vector2d box_max;
  };

  // Whether segment p -> q crosses frame `index` (half-open rules); if so its parameter along
  // p -> q in [0, 1] and its direction.
  bool crossing(int index, const Eigen::Vector2d& p, const Eigen::Vector2d& q, double& u,
                int& direction) const;
  // Calls visit(frame index) once for every frame that may cross p -> q.
  template <typename Visit>
  void forEachCandidate(const Eigen::Vector2d& p, const Eigen::Vector2d& q, Visit&& visit) const;
  void buildBuckets();

  std::vector<ReferenceFrame> frames_;
  std::vector<FrameGeometry> geometry_;
  Eigen::Vector2d anchor_ = Eigen::Vector2d::Zero();

  // Bucket grid over the frames' bounding box: bucket (row, col) holds the sorted indices
  // bucket_frames_[bucket_offsets_[b] .. bucket_offsets_[b + 1]) with b = row * cols + col.
  Eigen::Vector2d grid_min_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d grid_max_ = Eigen::Vector2d::Zero();
  double bucket_size_ = 1.0;
  double inverse_bucket_size_ = 1.0;
  int bucket_cols_ = 0;
  int bucket_rows_ = 0;
  std::vector<std::uint32_t> bucket_offsets_;
  std::vector<std::int32_t> bucket_frames_;
};

}  // namespace terratraj::search
