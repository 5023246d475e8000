#include "accel/kd_tree.h"

#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>

#include "accel/kd_traverse.h"
#include "accel/kd_traverse_setup.h"

namespace lancer {

namespace {

KdKernels checked_kernels(Isa isa) {
  if (!cpu_supports(isa))
    throw std::invalid_argument("kd-tree: this CPU does not support the " + std::string(isa_name(isa)) +
                                " instruction set");
  return select_kd_kernels(isa);
}

// The options with an automatic (0) intersection cost replaced by the ISA's constant.
KdBuildOptions resolved(KdBuildOptions options, Isa isa) {
  if (options.intersection_cost == 0.0f) options.intersection_cost = kd_intersection_cost(isa);
  return options;
}

}  // namespace

KdTree::KdTree(const TriangleSoA& tris, const KdBuildOptions& options, Isa isa)
    : options_(resolved(options, isa)), kernels_(checked_kernels(isa)), triangle_count_(tris.size()) {
  const auto start = std::chrono::steady_clock::now();
  KdBuildOutput built = build_kd_tree(tris, options_);
  bounds_ = built.bounds;
  max_extent_up_ = kd_max_extent_up(bounds_);
  depth_bound_ = built.depth_bound;
  reference_budget_ = built.reference_budget;
  references_ = built.prims.size();
  nodes_ = std::move(built.nodes);
  lay_out_leaves(tris, built);
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Copies each leaf's triangles, in leaf order, into SoA blocks of the kernels' width (the
// KdTriangleBlock layout); a leaf starts a new block, and its last block is padded with
// NaN triangles (never hit) and kNoHit indices.
void KdTree::lay_out_leaves(const TriangleSoA& tris, const KdBuildOutput& built) {
  const std::size_t W = static_cast<std::size_t>(kernels_.block_width);
  std::size_t slots = 0;
  for (const KdNode& n : nodes_)
    if (n.is_leaf()) slots += (n.count() + W - 1) / W * W;
  if (slots > kKdMaxOffset)
    throw std::length_error("kd-tree: " + std::to_string(slots) + " leaf slots exceed the 30-bit node offsets");

  blocks_.assign(slots * 9, std::numeric_limits<float>::quiet_NaN());
  leaf_prims_.assign(slots, kNoHit);

  std::size_t cursor = 0;
  for (KdNode& n : nodes_) {
    if (!n.is_leaf()) continue;
    const std::uint32_t first = n.first_slot(), count = n.count();
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t tri = built.prims[first + i];
      const std::size_t slot = cursor + i;
      float* lane = blocks_.data() + slot / W * 9 * W + slot % W;  // x[0] of this slot
      for (std::size_t k = 0; k < 3; ++k) {
        lane[k * W] = tris.x[k][tri];
        lane[(3 + k) * W] = tris.y[k][tri];
        lane[(6 + k) * W] = tris.z[k][tri];
      }
      leaf_prims_[slot] = tri;
    }
    n = KdNode::leaf(static_cast<std::uint32_t>(cursor), count);
    cursor += (count + W - 1) / W * W;
  }
}

glm::vec3 KdTree::slot_vertex(std::uint32_t slot, int k) const {
  const std::size_t w = static_cast<std::size_t>(block_width());
  const float* lane = blocks_.data() + slot / w * 9 * w + slot % w;
  return {lane[std::size_t(k) * w], lane[(3 + std::size_t(k)) * w], lane[(6 + std::size_t(k)) * w]};
}

void KdTree::intersect_packet(const Ray* rays, Hit* hits, int count) const {
  if (count < 0) throw std::invalid_argument("kd-tree: negative packet size " + std::to_string(count));
  constexpr int kPacket = 64;  // the kernels' packet size
  const KdTreeView v = view(*this);
  for (int i = 0; i < count; i += kPacket)
    kernels_.intersect_packet(v, rays + i, hits + i, count - i < kPacket ? count - i : kPacket);
}

void KdTree::occluded_packet(const Ray* rays, bool* occluded, int count) const {
  if (count < 0) throw std::invalid_argument("kd-tree: negative packet size " + std::to_string(count));
  constexpr int kPacket = 64;
  const KdTreeView v = view(*this);
  for (int i = 0; i < count; i += kPacket)
    kernels_.occluded_packet(v, rays + i, occluded + i, count - i < kPacket ? count - i : kPacket);
}

std::size_t KdTree::memory_bytes() const {
  return nodes_.capacity() * sizeof(KdNode) + leaf_prims_.capacity() * sizeof(std::uint32_t) +
         blocks_.capacity() * sizeof(float);
}

}  // namespace lancer
