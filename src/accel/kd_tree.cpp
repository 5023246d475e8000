#include "accel/kd_tree.h"

#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>

#include "accel/kd_traverse.h"

namespace lancer {

KdTree::KdTree(const TriangleSoA& tris, const KdBuildOptions& options)
    : options_(options), triangle_count_(tris.size()) {
  const auto start = std::chrono::steady_clock::now();
  KdBuildOutput built = build_kd_tree(tris, options);
  bounds_ = built.bounds;
  depth_bound_ = built.depth_bound;
  reference_budget_ = built.reference_budget;
  references_ = built.prims.size();
  nodes_ = std::move(built.nodes);
  lay_out_leaves(tris, built);
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Copies each leaf's triangles, in leaf order, into SoA blocks; a leaf starts a new block,
// and its last block is padded with NaN triangles (never hit) and kNoHit indices.
void KdTree::lay_out_leaves(const TriangleSoA& tris, const KdBuildOutput& built) {
  constexpr std::size_t W = kKdBlockWidth;
  std::size_t slots = 0;
  for (const KdNode& n : nodes_)
    if (n.is_leaf()) slots += (n.count() + W - 1) / W * W;
  if (slots > kKdMaxOffset)
    throw std::length_error("kd-tree: " + std::to_string(slots) + " leaf slots exceed the 30-bit node offsets");

  const float nan = std::numeric_limits<float>::quiet_NaN();
  blocks_.assign(slots / W, Block{});
  for (Block& b : blocks_)
    for (int k = 0; k < 3; ++k)
      for (std::size_t l = 0; l < W; ++l) b.x[k][l] = b.y[k][l] = b.z[k][l] = nan;
  leaf_prims_.assign(slots, kNoHit);

  std::size_t cursor = 0;
  for (KdNode& n : nodes_) {
    if (!n.is_leaf()) continue;
    const std::uint32_t first = n.first_slot(), count = n.count();
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t tri = built.prims[first + i];
      const std::size_t slot = cursor + i;
      Block& b = blocks_[slot / W];
      const std::size_t lane = slot % W;
      for (int k = 0; k < 3; ++k) {
        b.x[k][lane] = tris.x[k][tri];
        b.y[k][lane] = tris.y[k][tri];
        b.z[k][lane] = tris.z[k][tri];
      }
      leaf_prims_[slot] = tri;
    }
    n = KdNode::leaf(static_cast<std::uint32_t>(cursor), count);
    cursor += (count + W - 1) / W * W;
  }
}

Hit KdTree::intersect(const Ray& ray) const { return kd_intersect(view(*this), ray); }

bool KdTree::occluded(const Ray& ray) const { return kd_occluded(view(*this), ray); }

std::size_t KdTree::memory_bytes() const {
  return nodes_.capacity() * sizeof(KdNode) + leaf_prims_.capacity() * sizeof(std::uint32_t) +
         blocks_.capacity() * sizeof(Block);
}

}  // namespace lancer
