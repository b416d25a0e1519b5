#pragma once
// SpatialGridIndex: a uniform bucket grid over the map for the roadmap's neighbour queries, so
// that finding candidate nodes near a milestone costs about the same with 10 or 10^5 nodes.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace terratraj::search {

/// Node ids bucketed by position. Insert / remove O(1) (amortised; removal O(bucket size)).
class SpatialGridIndex {
 public:
  /// A grid covering [0, width] x [0, height] [m] with square buckets of `bucket_size` [m]
  /// (> 0). Positions outside are clamped to the border buckets.
  SpatialGridIndex(double width, double height, double bucket_size);

  /// Adds id at a position.
  void insert(std::int32_t id, const Eigen::Vector2d& position);
  /// Removes id (inserted at `position`); no effect if absent.
  void remove(std::int32_t id, const Eigen::Vector2d& position);
  /// Removes every id.
  void clear();
  /// Number of ids held.
  std::size_t size() const { return size_; }

  /// Collects into `out` (cleared first) the ids of the buckets in square rings around
  /// `position`, ring after ring, until at least `min_count` ids are collected or every bucket
  /// was visited. The ring that reaches min_count is completed, and one more ring is added, so
  /// the ids returned include every id within one bucket size of the nearest ones found.
  void gather(const Eigen::Vector2d& position, std::size_t min_count,
              std::vector<std::int32_t>& out) const;

 private:
  int bucketCol(double x) const;
  int bucketRow(double y) const;
  std::size_t bucketOf(const Eigen::Vector2d& position) const;

  double bucket_size_;
  int cols_;
  int rows_;
  std::size_t size_ = 0;
  std::vector<std::vector<std::int32_t>> buckets_;
};

}  // namespace terratraj::search
