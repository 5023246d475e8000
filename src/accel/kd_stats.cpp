#include "accel/kd_stats.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <cstdio>
#include <ostream>
#include <vector>

#include "accel/kd_build_types.h"
#include "accel/kd_tree.h"

namespace lancer {

KdStats compute_kd_stats(const KdTree& tree) {
  KdStats s;
  const std::vector<KdNode>& nodes = tree.nodes();
  s.triangles = tree.triangle_count();
  s.nodes = nodes.size();
  s.references = tree.references();
  s.reference_budget = tree.reference_budget();
  s.depth_bound = tree.depth_bound();
  s.memory_bytes = tree.memory_bytes();
  s.bytes_per_triangle = s.triangles ? double(s.memory_bytes) / double(s.triangles) : 0.0;
  s.build_ms = tree.build_ms();

  const double root_area = kd::surface_area(tree.bounds());
  const double ct = tree.options().traversal_cost, ci = tree.options().intersection_cost;
  struct Item {
    std::uint32_t node;
    int depth;
    Bounds3 cell;
  };
  std::vector<Item> todo{{0, 0, tree.bounds()}};
  double depth_sum = 0.0;
  std::size_t nonempty_tris = 0;
  while (!todo.empty()) {
    const Item it = todo.back();
    todo.pop_back();
    const KdNode& n = nodes[it.node];
    const double weight = root_area > 0.0 ? kd::surface_area(it.cell) / root_area : 1.0;
    if (n.is_leaf()) {
      ++s.leaves;
      if (n.count() == 0) ++s.empty_leaves;
      nonempty_tris += n.count();
      depth_sum += it.depth;
      if (it.depth > s.max_leaf_depth) s.max_leaf_depth = it.depth;
      s.sah_cost += ci * double(n.count()) * weight;
      continue;
    }
    ++s.inner_nodes;
    s.sah_cost += ct * weight;
    Bounds3 left = it.cell, right = it.cell;
    left.hi[n.axis()] = n.split();
    right.lo[n.axis()] = n.split();
    todo.push_back({n.left_child(), it.depth + 1, left});
    todo.push_back({n.right_child(), it.depth + 1, right});
  }
  s.mean_leaf_depth = s.leaves ? depth_sum / double(s.leaves) : 0.0;
  const std::size_t nonempty = s.leaves - s.empty_leaves;
  s.mean_triangles_per_leaf = nonempty ? double(nonempty_tris) / double(nonempty) : 0.0;
  return s;
}

void print_kd_stats(std::ostream& os, const KdStats& s) {
  char line[160];
  auto put = [&](const char* label, const char* fmt, auto value) {
    std::snprintf(line, sizeof line, fmt, value);
    os << "  " << label << line << '\n';
  };
  os << "kd-tree\n";
  put("triangles:              ", "%zu", s.triangles);
  put("nodes:                  ", "%zu", s.nodes);
  put("inner nodes:            ", "%zu", s.inner_nodes);
  put("leaves:                 ", "%zu", s.leaves);
  put("empty leaves:           ", "%zu", s.empty_leaves);
  put("references:             ", "%zu", s.references);
  put("reference budget:       ", "%zu", s.reference_budget);
  put("references / triangle:  ", "%.3f", s.triangles ? double(s.references) / double(s.triangles) : 0.0);
  put("max leaf depth:         ", "%d", s.max_leaf_depth);
  put("depth bound:            ", "%d", s.depth_bound);
  put("mean leaf depth:        ", "%.2f", s.mean_leaf_depth);
  put("triangles / leaf:       ", "%.2f (non-empty leaves)", s.mean_triangles_per_leaf);
  put("SAH cost:               ", "%.3f", s.sah_cost);
  put("memory:                 ", "%.2f MiB", double(s.memory_bytes) / (1024.0 * 1024.0));
  put("bytes / triangle:       ", "%.1f", s.bytes_per_triangle);
  put("build time:             ", "%.2f ms", s.build_ms);
}

KdWorkPerRay measure_kd_work(const KdTree& tree, std::span<const Ray> rays, bool occlusion) {
  KdWorkPerRay w;
  if (rays.empty()) return w;
  tbb::combinable<KdTraversalCounts> per_thread;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      KdTraversalCounts& c = per_thread.local();
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        if (occlusion)
                          tree.occluded_counted(rays[i], c);
                        else
                          tree.intersect_counted(rays[i], c);
                      }
                    });
  KdTraversalCounts total;
  per_thread.combine_each([&](const KdTraversalCounts& c) {
    total.inner_steps += c.inner_steps;
    total.leaves += c.leaves;
    total.triangle_tests += c.triangle_tests;
  });
  const double n = static_cast<double>(rays.size());
  w.inner_steps = static_cast<double>(total.inner_steps) / n;
  w.leaves = static_cast<double>(total.leaves) / n;
  w.triangle_tests = static_cast<double>(total.triangle_tests) / n;
  return w;
}

}  // namespace lancer
