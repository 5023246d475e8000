// Statistics of a built kd-tree, for `lancer info` and the benchmarks, and the work its
// single-ray kernels do on given rays, for `lancer trace` and `lancer bench`.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <span>

#include "accel/ray.h"

namespace lancer {

class KdTree;

struct KdStats {
  std::size_t triangles = 0;
  std::size_t nodes = 0;
  std::size_t inner_nodes = 0;
  std::size_t leaves = 0;
  std::size_t empty_leaves = 0;
  std::size_t references = 0;         // triangle references held by the leaves
  std::size_t reference_budget = 0;   // the build's bound on references
  int depth_bound = 0;
  int max_leaf_depth = 0;
  double mean_leaf_depth = 0.0;
  double mean_triangles_per_leaf = 0.0;  // over non-empty leaves
  // SAH cost of the final tree: sum over inner nodes of C_trav * SA(node) / SA(root) plus
  // over leaves of C_isect * count * SA(leaf) / SA(root), with the tree's cost constants.
  double sah_cost = 0.0;
  std::size_t memory_bytes = 0;
  double bytes_per_triangle = 0.0;
  double build_ms = 0.0;
};

KdStats compute_kd_stats(const KdTree& tree);

// A readable block, one quantity per line.
void print_kd_stats(std::ostream& os, const KdStats& stats);

// Mean work per ray of the single-ray kernel (intersect_counted, or occluded_counted with
// `occlusion`): inner-node steps, leaves entered, triangles tested (a SIMD leaf test counts
// the triangles in its lanes, not its width). All zero for no rays. One untimed pass,
// spread over the current task arena; the counts do not depend on the threads.
struct KdWorkPerRay {
  double inner_steps = 0.0, leaves = 0.0, triangle_tests = 0.0;
};
KdWorkPerRay measure_kd_work(const KdTree& tree, std::span<const Ray> rays, bool occlusion);

}  // namespace lancer
