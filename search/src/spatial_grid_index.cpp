#include "terratraj/search/spatial_grid_index.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::search {

SpatialGridIndex::SpatialGridIndex(double width, double height, double bucket_size)
    : bucket_size_(bucket_size > 0.0 ? bucket_size : 1.0),
      cols_(std::max(1, static_cast<int>(std::ceil(width / bucket_size_)))),
      rows_(std::max(1, static_cast<int>(std::ceil(height / bucket_size_)))),
      buckets_(static_cast<std::size_t>(cols_) * rows_) {}

int SpatialGridIndex::bucketCol(double x) const {
  const double c = std::floor(x / bucket_size_);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(cols_ - 1)));
}

int SpatialGridIndex::bucketRow(double y) const {
  const double r = std::floor(y / bucket_size_);
  return static_cast<int>(std::clamp(r, 0.0, static_cast<double>(rows_ - 1)));
}

std::size_t SpatialGridIndex::bucketOf(const Eigen::Vector2d& position) const {
  return static_cast<std::size_t>(bucketRow(position.y())) * cols_ + bucketCol(position.x());
}

void SpatialGridIndex::insert(std::int32_t id, const Eigen::Vector2d& position) {
  buckets_[bucketOf(position)].push_back(id);
  ++size_;
}

void SpatialGridIndex::remove(std::int32_t id, const Eigen::Vector2d& position) {
  std::vector<std::int32_t>& bucket = buckets_[bucketOf(position)];
  const auto it = std::find(bucket.begin(), bucket.end(), id);
  if (it == bucket.end()) return;
  *it = bucket.back();
  bucket.pop_back();
  --size_;
}

void SpatialGridIndex::clear() {
  for (std::vector<std::int32_t>& bucket : buckets_) bucket.clear();
  size_ = 0;
}

void SpatialGridIndex::gather(const Eigen::Vector2d& position, std::size_t min_count,
                              std::vector<std::int32_t>& out) const {
  out.clear();
  if (size_ == 0) return;
  const int col = bucketCol(position.x());
  const int row = bucketRow(position.y());
  const int max_ring = std::max({col, cols_ - 1 - col, row, rows_ - 1 - row});
  int extra_rings = -1;  // rings still to add once min_count is reached
  for (int ring = 0; ring <= max_ring; ++ring) {
    const int r0 = row - ring, r1 = row + ring, c0 = col - ring, c1 = col + ring;
    const auto take = [&](int r, int c) {
      const std::vector<std::int32_t>& bucket = buckets_[static_cast<std::size_t>(r) * cols_ + c];
      out.insert(out.end(), bucket.begin(), bucket.end());
    };
    for (int r = std::max(r0, 0); r <= std::min(r1, rows_ - 1); ++r) {
      if (r == r0 || r == r1) {
        for (int c = std::max(c0, 0); c <= std::min(c1, cols_ - 1); ++c) take(r, c);
      } else {
        // Inside the ring's rows only its first and last columns belong to it.
        if (c0 >= 0) take(r, c0);
        if (c1 < cols_ && c1 != c0) take(r, c1);
      }
    }
    if (extra_rings < 0 && out.size() >= min_count) extra_rings = 1;
    if (extra_rings == 0) break;
    if (extra_rings > 0) --extra_rings;
  }
}

}  // namespace terratraj::search
