// A balanced kd-tree over points with a k-nearest-neighbour query: the photon map's search
// structure (Jensen 1996, "Global Illumination using Photon Maps", sec. 2.3; Bentley 1975).
//
// Layout: implicit and flat. build() reorders the points so that the subtree over slots
// [lo, hi) keeps its splitting point at mid = lo + (hi - lo) / 2, its left subtree in
// [lo, mid) and its right one in [mid + 1, hi); axis_[mid] is the split's axis, the widest
// of the subtree's bounding box. No child pointers, depth ceil(log2(n + 1)).
//
// Ties: points compare on the split axis by (coordinate, index given to build()), and
// neighbours by (squared distance, index): both are strict total orders, so the tree and
// the k nearest are unique whatever std::nth_element does with equal keys, and a query
// gives exactly what a brute-force search with the same order gives.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace lancer {

class PointKdTree {
 public:
  struct Neighbour {
    float d2 = 0.0f;           // squared distance to the query point
    std::uint32_t index = 0;   // the point's index in build()'s input
    std::uint32_t slot = 0;    // its place in the tree (slot_point(slot) is the point)
    // The order neighbours are ranked by: nearer first, then lower index.
    bool before(const Neighbour& o) const { return d2 < o.d2 || (d2 == o.d2 && index < o.index); }
  };

  // Builds the tree over `points` (at most 2^32 - 1). Reuses its memory.
  void build(const std::vector<glm::vec3>& points);

  std::size_t size() const { return nodes_.size(); }
  bool empty() const { return nodes_.empty(); }
  const glm::vec3& slot_point(std::uint32_t slot) const { return nodes_[slot].p; }
  std::uint32_t slot_index(std::uint32_t slot) const { return nodes_[slot].index; }

  // The (at most) k points nearest to q within max_radius (|p - q| <= max_radius) among
  // those accept(slot) admits, by Neighbour::before. They are written to heap[0, count) as a
  // max-heap (heap[0] the farthest) and count is returned; heap must hold k entries. Nothing
  // is allocated. accept is called only for points within the current search radius.
  template <class Accept>
  int nearest(const glm::vec3& q, int k, float max_radius, Accept&& accept, Neighbour* heap) const;

 private:
  struct Node {
    glm::vec3 p;
    std::uint32_t index;
  };
  void build_range(std::uint32_t lo, std::uint32_t hi);

  std::vector<Node> nodes_;
  std::vector<std::uint8_t> axis_;  // per slot: the split axis of the subtree whose middle it is
};

namespace kd_heap {

// A max-heap under Neighbour::before over heap[0, n).
inline void sift_up(PointKdTree::Neighbour* heap, int i) {
  const PointKdTree::Neighbour x = heap[i];
  while (i > 0) {
    const int parent = (i - 1) / 2;
    if (!heap[parent].before(x)) break;
    heap[i] = heap[parent];
    i = parent;
  }
  heap[i] = x;
}

inline void sift_down(PointKdTree::Neighbour* heap, int n, int i) {
  const PointKdTree::Neighbour x = heap[i];
  for (;;) {
    int child = 2 * i + 1;
    if (child >= n) break;
    if (child + 1 < n && heap[child].before(heap[child + 1])) ++child;
    if (!x.before(heap[child])) break;
    heap[i] = heap[child];
    i = child;
  }
  heap[i] = x;
}

}  // namespace kd_heap

template <class Accept>
int PointKdTree::nearest(const glm::vec3& q, int k, float max_radius, Accept&& accept, Neighbour* heap) const {
  if (nodes_.empty() || k <= 0 || !(max_radius >= 0.0f)) return 0;
  const float max_d2 = max_radius * max_radius;
  int count = 0;
  // The radius beyond which nothing can enter: the search radius until the heap is full,
  // then its farthest neighbour. A point exactly at the bound may still enter by its index,
  // so subtrees are pruned only when strictly farther.
  float bound = max_d2;
  struct Todo {
    std::uint32_t lo, hi;
    float d2;  // lower bound of the squared distance from q to the subtree's points
  };
  Todo stack[64];  // a balanced tree over < 2^32 points is at most 33 deep: one far child per level
  int top = 0;
  stack[top++] = {0, static_cast<std::uint32_t>(nodes_.size()), 0.0f};
  while (top > 0) {
    const Todo t = stack[--top];
    if (t.d2 > bound) continue;
    std::uint32_t lo = t.lo, hi = t.hi;
    while (lo < hi) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      const Node& node = nodes_[mid];
      const glm::vec3 d = node.p - q;
      const float d2 = d.x * d.x + d.y * d.y + d.z * d.z;
      if (d2 <= bound) {
        const Neighbour n{d2, node.index, mid};
        if (count < k) {
          if (accept(mid)) {
            heap[count] = n;
            kd_heap::sift_up(heap, count++);
            if (count == k) bound = heap[0].d2;
          }
        } else if (n.before(heap[0]) && accept(mid)) {
          heap[0] = n;
          kd_heap::sift_down(heap, count, 0);
          bound = heap[0].d2;
        }
      }
      if (hi - lo == 1) break;
      const int axis = axis_[mid];
      const float diff = q[axis] - node.p[axis];
      // Left points have coordinates <= the split's, right ones >=: the far side is at least
      // |diff| away.
      const float far_d2 = diff * diff;
      if (diff <= 0.0f) {
        if (far_d2 <= bound && mid + 1 < hi) stack[top++] = {mid + 1, hi, far_d2};
        hi = mid;
      } else {
        if (far_d2 <= bound) stack[top++] = {lo, mid, far_d2};
        lo = mid + 1;
      }
    }
  }
  return count;
}

}  // namespace lancer
