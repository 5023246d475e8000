#include "render/point_kd_tree.h"

#include <algorithm>
#include <stdexcept>

#include <glm/common.hpp>

namespace lancer {

void PointKdTree::build(const std::vector<glm::vec3>& points) {
  if (points.size() >= 0xFFFFFFFFu) throw std::length_error("PointKdTree: too many points");
  nodes_.resize(points.size());
  axis_.assign(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) nodes_[i] = {points[i], static_cast<std::uint32_t>(i)};
  build_range(0, static_cast<std::uint32_t>(nodes_.size()));
}

// Median split on the widest axis of [lo, hi)'s bounds, then the two halves. Recursion
// depth is the tree's, about log2(n); the work O(n log n) (nth_element is linear).
void PointKdTree::build_range(std::uint32_t lo, std::uint32_t hi) {
  while (hi - lo > 1) {
    glm::vec3 lower = nodes_[lo].p, upper = nodes_[lo].p;
    for (std::uint32_t i = lo + 1; i < hi; ++i) {
      lower = glm::min(lower, nodes_[i].p);
      upper = glm::max(upper, nodes_[i].p);
    }
    const glm::vec3 extent = upper - lower;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::uint32_t mid = lo + (hi - lo) / 2;
    std::nth_element(nodes_.begin() + lo, nodes_.begin() + mid, nodes_.begin() + hi,
                     [axis](const Node& a, const Node& b) {
                       return a.p[axis] < b.p[axis] || (a.p[axis] == b.p[axis] && a.index < b.index);
                     });
    axis_[mid] = static_cast<std::uint8_t>(axis);
    // The halves differ by at most one point: recursion on one, the loop on the other.
    build_range(lo, mid);
    lo = mid + 1;
  }
}

}  // namespace lancer
