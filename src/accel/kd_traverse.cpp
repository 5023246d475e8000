// Single-ray kd-tree traversal: front to back with an explicit stack (Havran's TA_B^rec in
// iterative form, as in pbrt's KdTreeAggregate::Intersect), written from scratch.
//
// Exactness. Every triangle is tested with the oracle's watertight kernel against the
// whole ray range [tnear, best), so a triangle's t, u, v do not depend on the leaf it is
// found in. Ties across leaves: the kernel is asked for t <= best.t, and the lower
// triangle index wins an exact tie, as in the oracle. What remains is to visit every leaf
// that can hold the oracle's answer before stopping. The computed t of a triangle can
// differ from the exact ray parameter of the exact hit point by rounding (a few ulps
// relative to t for a well-shaped triangle, more for grazing ones), so ray/plane distances
// are computed in double and every cell interval is widened by a slack
//   slack(t) = |t| * kRelativeSlack + kExtentSlack * (largest scene extent) / max|dir|,
// the root interval is [tnear - slack, tfar + slack] clipped to the widened scene box,
// and the search stops only once best.t < next entry - slack. Widening costs only an extra
// leaf visit for hits within the slack of a cell boundary.
//
// Axis-parallel rays: a zero direction component never divides; the ray stays on one side
// of a split plane, or visits both children when it lies exactly in the plane (no 0 * inf).
//
// Where the kernel's own arithmetic breaks down, the error bound above does not hold, so
// those rays scan every leaf slot instead (exact by construction, O(references)):
//  - a NaN or infinite origin or direction (the kernel gives t = 0 "hits" for an infinite
//    direction, and the scan reproduces them);
//  - scales where the kernel's products underflow or overflow in float: with E the largest
//    scene extent and D the distance scale from the origin to the scene, when
//    E^2 * max(E, D) / max|dir| < 2^-60 (e.g. a 1e-6 scene and unit directions: the kernel
//    then returns t = 0 for triangles anywhere on the ray's line) or > 2^100, or E > 2^50.
// A zero direction never hits (the kernel's shear constants are NaN). One limit remains:
// a triangle far smaller than the scene (edges below ~1e-6 E at the threshold scale, or
// below ~1e-19 of a unit-scale ray's reach) has products that underflow on its own, and its
// t can then be off by more than the slack.
#include "accel/kd_traverse.h"

#include <cmath>
#include <limits>

#include "accel/kd_tree.h"
#include "accel/watertight.h"

namespace lancer {
namespace {

constexpr double kRelativeSlack = 1.0 / 65536.0;  // 2^-16 = 256 float ulps of t
constexpr double kExtentSlack = 1.0 / 65536.0;

struct TraversalRay {
  double org[3];
  double inv_dir[3];
  bool parallel[3];   // dir[axis] == 0: never crosses a plane of that axis
  bool negative[3];   // dir[axis] < 0: the right child comes first
  double abs_slack;

  double slack(double t) const { return std::fabs(t) * kRelativeSlack + abs_slack; }
};

struct StackEntry {
  std::uint32_t node;
  double tmin, tmax;
};

enum class Plan { Miss, Traverse, Scan };

// Sets up the ray and clips [tnear, tfar] to the scene box (both widened by the slack),
// or says why the ray does not traverse (see the header comment).
Plan setup(const KdTreeView& tree, const Ray& ray, TraversalRay& tr, double& t0, double& t1) {
  if (tree.bounds.empty()) return Plan::Miss;
  double max_dir = 0.0, max_extent = 0.0, distance = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(ray.org[a]) || !std::isfinite(ray.dir[a])) return Plan::Scan;
    const double lo = tree.bounds.lo[a], hi = tree.bounds.hi[a];
    max_dir = std::fmax(max_dir, std::fabs(double(ray.dir[a])));
    max_extent = std::fmax(max_extent, hi - lo);
    distance = std::fmax(distance, std::fmax(std::fabs(ray.org[a] - lo), std::fabs(ray.org[a] - hi)));
  }
  if (max_dir == 0.0) return Plan::Miss;
  const double magnitude = max_extent * max_extent * std::fmax(max_extent, distance) / max_dir;
  if (magnitude < 0x1p-60 || magnitude > 0x1p100 || max_extent > 0x1p50) return Plan::Scan;

  tr.abs_slack = kExtentSlack * max_extent / max_dir;
  t0 = double(ray.tnear);
  t1 = double(ray.tfar);
  t0 -= tr.slack(t0);
  t1 += tr.slack(t1);
  for (int a = 0; a < 3; ++a) {
    tr.org[a] = ray.org[a];
    tr.parallel[a] = ray.dir[a] == 0.0f;
    tr.negative[a] = ray.dir[a] < 0.0f;
    tr.inv_dir[a] = tr.parallel[a] ? 0.0 : 1.0 / double(ray.dir[a]);
    const double lo = tree.bounds.lo[a], hi = tree.bounds.hi[a];
    if (tr.parallel[a]) {
      if (tr.org[a] < lo || tr.org[a] > hi) return Plan::Miss;
      continue;
    }
    double ta = (lo - tr.org[a]) * tr.inv_dir[a], tb = (hi - tr.org[a]) * tr.inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::fmax(t0, ta - tr.slack(ta));
    t1 = std::fmin(t1, tb + tr.slack(tb));
  }
  return t0 <= t1 ? Plan::Traverse : Plan::Miss;  // Miss for NaN tnear or tfar too
}

// Moves from an inner node to the child (or children) the ray's interval overlaps.
// Returns the node to visit next and narrows [tmin, tmax]; pushes the far child when both
// are visited.
inline std::uint32_t descend(const KdNode& n, const TraversalRay& tr, double& tmin, double& tmax,
                             StackEntry* stack, int& sp) {
  const int a = n.axis();
  const double split = n.split();
  const std::uint32_t left = n.left_child();
  if (tr.parallel[a]) {
    if (tr.org[a] < split) return left;
    if (tr.org[a] > split) return left + 1;
    stack[sp++] = {left + 1, tmin, tmax};  // lies in the plane: both cells
    return left;
  }
  const double tp = (split - tr.org[a]) * tr.inv_dir[a];
  const double s = tr.slack(tp);
  const std::uint32_t first = tr.negative[a] ? left + 1 : left;
  const std::uint32_t second = tr.negative[a] ? left : left + 1;
  const bool visit_first = tp + s >= tmin;
  const bool visit_second = tp - s <= tmax;
  if (visit_first && visit_second) {
    stack[sp++] = {second, std::fmax(tmin, tp - s), tmax};
    tmax = std::fmin(tmax, tp + s);
    return first;
  }
  if (visit_first) {
    tmax = std::fmin(tmax, tp + s);
    return first;
  }
  tmin = std::fmax(tmin, tp - s);
  return second;
}

inline void load_triangle(const KdTreeView& tree, std::uint32_t slot, glm::vec3 v[3]) {
  const KdTriangleBlock<kKdBlockWidth>& b = tree.blocks[slot / kKdBlockWidth];
  const std::uint32_t lane = slot % kKdBlockWidth;
  for (int k = 0; k < 3; ++k) v[k] = glm::vec3(b.x[k][lane], b.y[k][lane], b.z[k][lane]);
}

// Tests every leaf slot with the oracle's rule: the answer cannot depend on the tree.
Hit scan_intersect(const KdTreeView& tree, const Ray& ray) {
  const WatertightRay wr(ray);
  Hit best;
  for (std::uint32_t slot = 0; slot < tree.slot_count; ++slot) {
    const std::uint32_t prim = tree.prims[slot];
    if (prim == kNoHit) continue;
    glm::vec3 v[3];
    load_triangle(tree, slot, v);
    const float limit = best.valid() ? std::nextafter(best.t, kInfinity) : ray.tfar;
    TriangleHit th;
    if (intersect_watertight(wr, v[0], v[1], v[2], limit, th) && (!best.valid() || th.t < best.t || prim < best.prim))
      best = {th.t, prim, th.u, th.v};
  }
  return best;
}

bool scan_occluded(const KdTreeView& tree, const Ray& ray) {
  const WatertightRay wr(ray);
  for (std::uint32_t slot = 0; slot < tree.slot_count; ++slot) {
    if (tree.prims[slot] == kNoHit) continue;
    glm::vec3 v[3];
    load_triangle(tree, slot, v);
    TriangleHit th;
    if (intersect_watertight(wr, v[0], v[1], v[2], ray.tfar, th)) return true;
  }
  return false;
}

}  // namespace

KdTreeView view(const KdTree& tree) {
  return {tree.nodes().data(), tree.blocks().data(), tree.leaf_prims().data(),
          static_cast<std::uint32_t>(tree.leaf_prims().size()), tree.bounds()};
}

namespace {

// Counting hooks: NoCounts compiles to nothing, so kd_intersect pays no cost for them.
struct NoCounts {
  void step() {}
  void leaf() {}
  void test() {}
};
struct Counting {
  KdTraversalCounts& c;
  void step() { ++c.inner_steps; }
  void leaf() { ++c.leaves; }
  void test() { ++c.triangle_tests; }
};

template <typename Counter>
Hit intersect_closest(const KdTreeView& tree, const Ray& ray, Counter counter) {
  Hit best;
  TraversalRay tr;
  double tmin, tmax;
  const Plan plan = setup(tree, ray, tr, tmin, tmax);
  if (plan == Plan::Miss) return best;
  if (plan == Plan::Scan) return scan_intersect(tree, ray);

  const WatertightRay wr(ray);
  bool has_hit = false;
  float best_t = ray.tfar;
  StackEntry stack[kKdStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  for (;;) {
    const KdNode n = tree.nodes[node];
    if (!n.is_leaf()) {
      counter.step();
      node = descend(n, tr, tmin, tmax, stack, sp);
      continue;
    }
    counter.leaf();
    const std::uint32_t first = n.first_slot(), end = first + n.count();
    for (std::uint32_t slot = first; slot < end; ++slot) {
      counter.test();
      glm::vec3 v[3];
      load_triangle(tree, slot, v);
      // Accept t == best_t too, so an exact tie can go to the lower index.
      const float limit = has_hit ? std::nextafter(best_t, kInfinity) : ray.tfar;
      TriangleHit th;
      if (!intersect_watertight(wr, v[0], v[1], v[2], limit, th)) continue;
      const std::uint32_t prim = tree.prims[slot];
      if (!has_hit || th.t < best_t || prim < best.prim) {
        best = {th.t, prim, th.u, th.v};
        best_t = th.t;
        has_hit = true;
      }
    }
    // Next cell on the stack that can still hold a hit at or before best_t.
    for (;;) {
      if (sp == 0) return best;
      const StackEntry& e = stack[--sp];
      if (has_hit && double(best_t) < e.tmin - tr.slack(e.tmin)) continue;
      node = e.node;
      tmin = e.tmin;
      tmax = e.tmax;
      break;
    }
  }
}

}  // namespace

Hit kd_intersect(const KdTreeView& tree, const Ray& ray) { return intersect_closest(tree, ray, NoCounts{}); }

Hit kd_intersect_counted(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts) {
  return intersect_closest(tree, ray, Counting{counts});
}

bool kd_occluded(const KdTreeView& tree, const Ray& ray) {
  TraversalRay tr;
  double tmin, tmax;
  const Plan plan = setup(tree, ray, tr, tmin, tmax);
  if (plan == Plan::Miss) return false;
  if (plan == Plan::Scan) return scan_occluded(tree, ray);

  const WatertightRay wr(ray);
  StackEntry stack[kKdStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  for (;;) {
    const KdNode n = tree.nodes[node];
    if (!n.is_leaf()) {
      node = descend(n, tr, tmin, tmax, stack, sp);
      continue;
    }
    const std::uint32_t first = n.first_slot(), end = first + n.count();
    for (std::uint32_t slot = first; slot < end; ++slot) {
      glm::vec3 v[3];
      load_triangle(tree, slot, v);
      TriangleHit th;
      if (intersect_watertight(wr, v[0], v[1], v[2], ray.tfar, th)) return true;
    }
    if (sp == 0) return false;
    const StackEntry& e = stack[--sp];
    node = e.node;
    tmin = e.tmin;
    tmax = e.tmax;
  }
}

}  // namespace lancer
