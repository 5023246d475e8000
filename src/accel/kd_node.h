// The kd-tree's compact layout: 8-byte nodes and SoA triangle blocks in leaf order.
//
// Node layout follows the idea of Mitsuba's KDNode and pbrt's KdTreeNode (8 bytes, one
// offset for both children), written from scratch:
//   bits_        inner: the split position (float bits); leaf: the triangle count
//   flags_offset low 2 bits: 0, 1, 2 = split axis of an inner node, 3 = leaf;
//                high 30 bits: inner: index of the left child, the right child is the
//                next node; leaf: first slot of its range in the leaf arrays.
// kd_traverse-inl.h decodes the same two words itself (per-ISA code calls no inline
// function of namespace lancer, see STYLE.md example 3), so keep the two in step.
// Invariants: nodes[0] is the root; children pairs are stored side by side; a leaf's
// slots start at a multiple of the block width and hold `count` triangles in ascending
// triangle index, followed by padding up to the next multiple of the width.
#pragma once

#include <bit>
#include <cstdint>

namespace lancer {

// Offsets have 30 bits: node and slot indices must stay below this.
inline constexpr std::uint32_t kKdMaxOffset = (1u << 30) - 1;

// Hard cap on the tree depth (the automatic bound 8 + 1.3 log2 N stays below it for
// N < 2^30). The traversal pushes at most one entry per level, so a stack of
// kKdStackSize entries can never overflow.
inline constexpr int kKdMaxDepth = 48;
inline constexpr int kKdStackSize = 64;
static_assert(kKdMaxDepth < kKdStackSize, "the traversal stack must hold one entry per level");

class KdNode {
 public:
  static constexpr std::uint32_t kLeafFlag = 3;

  static KdNode inner(int axis, float split, std::uint32_t left_child) {
    KdNode n;
    n.bits_ = std::bit_cast<std::uint32_t>(split);
    n.flags_offset_ = (left_child << 2) | static_cast<std::uint32_t>(axis);
    return n;
  }
  static KdNode leaf(std::uint32_t first_slot, std::uint32_t count) {
    KdNode n;
    n.bits_ = count;
    n.flags_offset_ = (first_slot << 2) | kLeafFlag;
    return n;
  }

  bool is_leaf() const { return (flags_offset_ & 3u) == kLeafFlag; }
  int axis() const { return static_cast<int>(flags_offset_ & 3u); }
  float split() const { return std::bit_cast<float>(bits_); }
  std::uint32_t left_child() const { return flags_offset_ >> 2; }
  std::uint32_t right_child() const { return (flags_offset_ >> 2) + 1; }
  std::uint32_t first_slot() const { return flags_offset_ >> 2; }
  std::uint32_t count() const { return bits_; }

  // Same node with its offset moved by `delta` (used when subtrees are concatenated).
  KdNode relocated(std::uint32_t delta) const {
    KdNode n = *this;
    n.flags_offset_ = ((offset() + delta) << 2) | (flags_offset_ & 3u);
    return n;
  }
  std::uint32_t offset() const { return flags_offset_ >> 2; }

  bool operator==(const KdNode&) const = default;

 private:
  std::uint32_t bits_ = 0;
  std::uint32_t flags_offset_ = kLeafFlag;
};

static_assert(sizeof(KdNode) == 8, "kd-tree nodes are 8 bytes");

// W triangles of one leaf in structure-of-arrays form: vertex k of lane i is
// (x[k][i], y[k][i], z[k][i]), bit-identical to the input TriangleSoA. Padding lanes hold
// NaN vertices, which the watertight kernel never reports as a hit. KdTree stores its blocks
// as a flat float array with this layout (9 * W floats per block), W chosen per tree to
// match the traversal's vector width (kd_block_width in kd_traverse.h).
template <int W>
struct alignas(W * 4 < 64 ? W * 4 : 64) KdTriangleBlock {
  static_assert(W == 4 || W == 8 || W == 16, "block width is 4, 8 or 16");
  static constexpr int kWidth = W;
  float x[3][W];
  float y[3][W];
  float z[3][W];
};

// The widest block any traversal kernel uses (AVX-512: 16 lanes).
inline constexpr int kKdMaxBlockWidth = 16;

}  // namespace lancer
