#include "terratraj/search/prm_roadmap.hpp"

#include <algorithm>

namespace terratraj::search {

std::int32_t PrmRoadmap::add(const PrmNode& node) {
  nodes_.push_back(node);
  return static_cast<std::int32_t>(nodes_.size() - 1);
}

std::vector<std::int32_t> PrmRoadmap::pathTo(std::int32_t id) const {
  std::vector<std::int32_t> path;
  for (std::int32_t at = id; at != kNoParent; at = node(at).parent) path.push_back(at);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace terratraj::search
