// The build driver: root refs and events, the recursion, parallel subtrees, concatenation.
//
// Determinism: every decision depends only on the node's input (refs in ascending
// triangle index, events in a strict total order), never on timing. Nodes with many refs
// build their two children as separate oneTBB tasks, each into its own node and index
// arrays, and the parent concatenates them in the fixed order (left, right) with the
// offsets relocated. So the arrays are bytewise the same whatever the thread count.
//
// Memory bound: the root gets a budget of ceil(reference_factor * N) + 1 references; a
// split is refused (the node becomes a leaf) when its children would hold more references
// than its budget, and the children share the budget in proportion to their ref counts,
// so the leaves hold at most the root budget in total. Each level of the tree holds at most
// that many refs in its non-empty cells, so there are at most 2 * budget * depth_bound + 1
// nodes, and the depth is capped by kd_depth_bound().
//
// Peak memory: a node of n refs holds 28 n bytes of refs and 48 n of sorted events. A
// big node (at least kParallelThreshold refs) splices events into its left child only,
// which its thread builds next, freeing its own axis by axis before the children's refs
// are made, and writes the left refs over its own; its right child, which may wait for a
// thread, holds refs only and sorts its own events when it starts. Waiting nodes, which
// together hold about as many refs as the scene has triangles, then cost 28 bytes per ref
// instead of 76, and the root's split needs about 93 bytes per triangle at once (refs,
// events, one child axis, scratch) where splicing into both children needed about 160.
// The big lists come from BigBlockAllocator, so that freed ones leave the process at
// once. Small subtrees splice into both children (Wald & Havran) in per-thread reused
// buffers. Splicing is one pass and sorting five, so the right children's sorts cost
// 20-35 % of a one-thread build (rings-6: 2.5 -> 3.0 s), about nothing on two threads.
//
// The lean build (inputs below KdBuildOptions::one_thread_below triangles, 65,536 by
// default): the whole build runs on the calling thread (no oneTBB task: not even oneTBB's
// own allocations can fail there), and nodes of at least kLeanBigNode
// refs hold refs only: find_sah_split_axis_by_axis makes, sorts and sweeps one axis of
// events at a time (28 + 32 bytes per ref at once instead of 28 + 64), and both children
// sort their own events. Below some 10^5 triangles the fixed costs of two threads (both
// top-level subtrees with their events at once, each thread's freed lists in its own
// malloc arena, whose top malloc_trim never returns) were most of the peak. Measured with
// `lancer-spd-scaling --peak-of` (the 2-vCPU AMD EPYC, bytes per triangle of generation
// and build, two threads -> lean): rings-1 (11,522 triangles) 262-288 -> 168-170, mount-6
// 260-278 -> 154-160, balls-2 199-202 -> 147-149. The tree is the same bytes; the build
// takes up to 1.6x as long (AVX-512 tree, rings-2, 57,602 triangles: 92-104 -> 125-162 ms).
#include "accel/kd_build.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/task_group.h>

#include "accel/kd_build_events.h"
#include "accel/kd_build_naive.h"
#include "accel/kd_build_partition.h"
#include "simd/release_free_memory.h"

namespace lancer {
namespace kd {
namespace {

// Nodes with at least this many refs split with parallel sweeps and build their children
// as separate tasks; smaller subtrees are built sequentially into one array.
constexpr std::size_t kParallelThreshold = 4096;
// In a lean build, nodes with at least this many refs are built as big nodes (refs only,
// splits found axis by axis): a smaller sequential subtree holds at most about twice its
// refs' 76 bytes each.
constexpr std::size_t kLeanBigNode = 1024;

// Inputs beyond this many triangles could overflow the 30-bit offsets.
constexpr std::size_t kMaxTriangles = std::size_t(1) << 28;

struct Context {
  const TriangleSoA& tris;
  const KdBuildOptions& options;
  CostModel model;
  int depth_bound;
  // One thread (the caller's, no task is spawned), least memory: big nodes find their
  // split axis by axis and hold refs only.
  bool lean;
};

// A built subtree: nodes[0] is its root, offsets are local to these arrays.
struct Subtree {
  std::vector<KdNode> nodes;
  std::vector<std::uint32_t> prims;
};

SplitChoice choose_split(const Context& ctx, const NodeInput& in, bool parallel) {
  const std::size_t n = in.refs.size();
  if (n == 0 || in.depth >= ctx.depth_bound) return {};
  // A cell that is a segment or a point holds only degenerate triangles: nothing to gain.
  if (!(surface_area(in.cell) > 0.0)) return {};
  switch (ctx.options.split) {
    case KdSplit::Sah: {
      SplitChoice c = in.events.empty() ? find_sah_split_axis_by_axis(in.refs, in.cell, ctx.model)
                                        : find_sah_split(in.events, n, in.cell, ctx.model, parallel);
      // Leaf when no split is cheaper than intersecting every triangle (Wald & Havran).
      if (!c.found || !(c.cost < ctx.model.intersection * double(n))) return {};
      return c;
    }
    case KdSplit::Middle:
      return n <= ctx.options.naive_leaf_size ? SplitChoice{} : choose_middle_split(in);
    case KdSplit::Median:
      return n <= ctx.options.naive_leaf_size ? SplitChoice{} : choose_median_split(in);
  }
  return {};
}

void emit_leaf(const NodeInput& in, Subtree& out, std::size_t slot) {
  const auto first = static_cast<std::uint32_t>(out.prims.size());
  for (const Ref& r : in.refs) out.prims.push_back(r.tri);
  out.nodes[slot] = KdNode::leaf(first, static_cast<std::uint32_t>(in.refs.size()));
}

// Depth-first into one array: the node goes to out.nodes[slot], its children pair is
// appended at the end. `in` is handed to `scratch` for reuse once done with.
void emit_sequential(const Context& ctx, NodeInput& in, Subtree& out, std::size_t slot, BuildScratch& scratch) {
  const SplitChoice c = choose_split(ctx, in, false);
  NodeInput left, right;
  if (!c.found || !partition_node(ctx.tris, in, c, false, false, left, right, scratch)) {
    emit_leaf(in, out, slot);
    scratch.recycle(in);
    return;
  }
  const std::size_t pair = out.nodes.size();
  out.nodes.resize(pair + 2);
  out.nodes[slot] = KdNode::inner(c.axis, c.pos, static_cast<std::uint32_t>(pair));
  emit_sequential(ctx, left, out, pair, scratch);
  emit_sequential(ctx, right, out, pair + 1, scratch);
}

KdNode relocate(const KdNode& n, std::size_t node_shift, std::size_t prim_shift) {
  return n.relocated(static_cast<std::uint32_t>(n.is_leaf() ? prim_shift : node_shift));
}

// Root (inner, children at 1 and 2), then the two roots, then the rest of the left
// subtree, then the rest of the right one. A local node index k >= 1 of the left subtree
// moves to k + 2, of the right one to k + left.nodes.size() + 1.
Subtree concatenate(const SplitChoice& c, Subtree&& left, Subtree&& right) {
  Subtree out;
  const std::size_t left_shift = 2, right_shift = left.nodes.size() + 1, prim_shift = left.prims.size();
  out.nodes.reserve(1 + left.nodes.size() + right.nodes.size());
  out.nodes.push_back(KdNode::inner(c.axis, c.pos, 1));
  out.nodes.push_back(relocate(left.nodes[0], left_shift, 0));
  out.nodes.push_back(relocate(right.nodes[0], right_shift, prim_shift));
  for (std::size_t k = 1; k < left.nodes.size(); ++k) out.nodes.push_back(relocate(left.nodes[k], left_shift, 0));
  for (std::size_t k = 1; k < right.nodes.size(); ++k)
    out.nodes.push_back(relocate(right.nodes[k], right_shift, prim_shift));
  out.prims = std::move(left.prims);
  out.prims.insert(out.prims.end(), right.prims.begin(), right.prims.end());
  return out;
}

Subtree build_subtree(const Context& ctx, NodeInput& in) {
  Subtree out;
  out.nodes.resize(1);
  BuildScratch scratch;
  // Big nodes hand their children refs only (partition_node): events are sorted here,
  // when the node starts, the same lists splicing would have given. In a lean build a big
  // node never holds all three axes: choose_split sorts and sweeps one at a time.
  const bool big = in.refs.size() >= (ctx.lean ? kLeanBigNode : kParallelThreshold);
  if (ctx.options.split == KdSplit::Sah && in.events.empty() && !(ctx.lean && big))
    in.events = make_sorted_events(in.refs);
  if (!big) {
    emit_sequential(ctx, in, out, 0, scratch);
    return out;
  }
  const SplitChoice c = choose_split(ctx, in, !ctx.lean);
  NodeInput left, right;
  const bool split = c.found && partition_node(ctx.tris, in, c, true, !ctx.lean, left, right, scratch);
  scratch = {};  // the parent's vectors: free them before the subtrees are built
  if (!split) {
    emit_leaf(in, out, 0);
    return out;
  }
  // A lean build has one thread: left, then right. Otherwise the left child, which has its
  // events, goes on in this thread; the right one holds only refs while it waits for one.
  Subtree l, r;
  if (ctx.lean) {
    l = build_subtree(ctx, left);
    r = build_subtree(ctx, right);
    return concatenate(c, std::move(l), std::move(r));
  }
  tbb::task_group right_task;
  right_task.run([&] { r = build_subtree(ctx, right); });
  l = build_subtree(ctx, left);
  right_task.wait();
  return concatenate(c, std::move(l), std::move(r));
}

bool finite_triangle(const TriangleSoA& t, std::size_t i) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(t.x[k][i]) || !std::isfinite(t.y[k][i]) || !std::isfinite(t.z[k][i])) return false;
  return true;
}

void check_options(const KdBuildOptions& o) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("KdBuildOptions: " + what); };
  if (!(o.traversal_cost > 0.0f) || !std::isfinite(o.traversal_cost)) bad("traversal_cost must be positive and finite");
  if (!(o.intersection_cost > 0.0f) || !std::isfinite(o.intersection_cost))
    bad("intersection_cost must be positive and finite (KdTree fills in 0 for its ISA)");
  if (!(o.empty_space_factor > 0.0f && o.empty_space_factor <= 1.0f)) bad("empty_space_factor must be in (0, 1]");
  if (!(o.reference_factor >= 1.0f && o.reference_factor <= 16.0f)) bad("reference_factor must be in [1, 16]");
  if (o.max_depth < 0) bad("max_depth must be >= 0 (0: automatic)");
  if (o.naive_leaf_size < 1) bad("naive_leaf_size must be >= 1");
}

}  // namespace
}  // namespace kd

int kd_depth_bound(std::size_t n, int requested) {
  if (requested > 0) return requested < kKdMaxDepth ? requested : kKdMaxDepth;
  const double bound = n <= 1 ? 8.0 : std::round(8.0 + 1.3 * std::log2(double(n)));
  return bound < kKdMaxDepth ? static_cast<int>(bound) : kKdMaxDepth;
}

KdBuildOutput build_kd_tree(const TriangleSoA& tris, const KdBuildOptions& options) {
  kd::check_options(options);
  if (tris.size() > kd::kMaxTriangles)
    throw std::length_error("kd-tree: " + std::to_string(tris.size()) + " triangles exceed the limit of " +
                            std::to_string(kd::kMaxTriangles));
  KdBuildOutput out;
  kd::NodeInput root;
  root.refs.reserve(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (!kd::finite_triangle(tris, i)) continue;
    const Bounds3 b = tris.triangle_bounds(i);
    root.refs.push_back({static_cast<std::uint32_t>(i), b});
    out.bounds.extend(b);
  }
  const std::size_t n = root.refs.size();
  out.depth_bound = kd_depth_bound(n, options.max_depth);
  // Capped at the 30-bit offset range, so no node's ref indices can overflow an Event key.
  out.reference_budget = std::min<std::size_t>(
      static_cast<std::size_t>(std::ceil(double(options.reference_factor) * double(n))) + 1, kKdMaxOffset);
  root.cell = out.bounds;
  root.budget = out.reference_budget;

  const bool one_thread = n >= kd::kParallelThreshold && tris.size() < options.one_thread_below;
  const kd::Context ctx{tris, options,
                        {options.traversal_cost, options.intersection_cost, options.empty_space_factor},
                        out.depth_bound, one_thread};
  kd::Subtree tree = kd::build_subtree(ctx, root);
  if (tree.nodes.size() > kKdMaxOffset || tree.prims.size() > kKdMaxOffset)
    throw std::length_error("kd-tree: " + std::to_string(tree.nodes.size()) + " nodes and " +
                            std::to_string(tree.prims.size()) + " references exceed the 30-bit node offsets");
  out.nodes = std::move(tree.nodes);
  out.prims = std::move(tree.prims);
  // The build's small working vectors, before the tree is laid out.
  if (options.hand_back_memory) release_free_memory();
  return out;
}

}  // namespace lancer
