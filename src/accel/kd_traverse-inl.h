// Single-ray kd-tree traversal, as templates over the vector width N and the leaf block
// width B (a multiple of N), compiled once per ISA inside namespace lancer::LANCER_ISA by
// kd_traverse_<isa>.cpp. Front to back with an explicit stack (Havran's TA_B^rec in
// iterative form, as in pbrt's KdTreeAggregate::Intersect); in a leaf one ray is tested
// against N triangles at once from the SoA blocks. Written from scratch.
//
// Exactness. Every triangle is tested with the oracle's watertight arithmetic (Woop et al.
// 2013, watertight.h) against the whole ray range [tnear, best], lane by lane the same
// operations in the same order: explicit multiply then add/subtract (no FMA; the build
// passes -ffp-contract=off and this file never calls the fmadd wrappers), IEEE division
// for t and 1/det. Lanes where an edge function U, V or W is exactly 0 go to the scalar
// kernel itself (kd_slot_hit), which recomputes them in double as the oracle does. So a
// triangle's t, u, v do not depend on the leaf or lane it is found in. Ties across leaves:
// a hit with t == best.t still counts, and the lower triangle index wins an exact tie, as
// in the oracle. What remains is to visit every leaf that can hold the oracle's answer
// before stopping. The computed t of a triangle can differ from the exact ray parameter of
// the exact hit point by rounding (a few ulps relative to t for a well-shaped triangle,
// more for grazing ones), so every cell interval is widened by a slack
//   slack(t) = |t| * kKdRelativeSlack + kKdExtentSlack * (largest scene extent) / max|dir|
// (kd_traverse_setup.h), the root interval is [tnear - slack, tfar + slack] clipped to the
// widened scene box, and the search stops only once best.t < next entry - slack. Widening
// costs only an extra leaf visit for hits within the slack of a cell boundary.
//
// Plane distances (split - org) / dir are computed in float when the setup finds every
// quantity of the ray's traversal within [2^-100, 2^66] (or 0): then the subtraction, the
// reciprocal and the product each round once (relative error < 2^-22 in all), which the
// 2^-20 term of kKdRelativeSlack covers, on top of the 2^-16 kept for the kernel. Rays
// outside that range (directions with components below 2^-64 of the scene's reach, say)
// take the same loop in double, where those roundings are below 2^-50.
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
//
// ODR: everything here lives in lancer::LANCER_ISA, and the code calls no inline function
// of namespace lancer or std (it decodes KdNode's two words itself, see kd_node.h), so no
// copy compiled with one ISA's flags can stand in for another's.
#pragma once

#include "simd/isa_namespace.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "accel/kd_node.h"
#include "accel/kd_ray_setup-inl.h"
#include "accel/kd_traverse.h"
#include "accel/kd_traverse_setup.h"
#include "accel/ray.h"

namespace lancer::LANCER_ISA {
namespace kd {

inline float bits_to_float(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, sizeof f);
  return f;
}

// The next float above a finite x (std::nextafter(x, +inf) without the libm call).
inline float next_up(float x) {
  if (x == 0.0f) return 0x1p-149f;
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  b = x > 0.0f ? b + 1 : b - 1;
  return bits_to_float(b);
}

// KdNode's two words (kd_node.h): split bits or count; offset << 2 | axis (3 = leaf).
struct NodeWords {
  std::uint32_t bits;
  std::uint32_t flags_offset;
};
static_assert(sizeof(NodeWords) == sizeof(KdNode));

inline NodeWords read_node(const KdNode* nodes, std::uint32_t i) {
  NodeWords n;
  std::memcpy(&n, nodes + i, sizeof n);
  return n;
}

// The traversal's per-ray constants, in float or (rare rays) double.
//
// Where the slack goes. The rule above compares each plane crossing, widened by its slack,
// with the cell's widened interval: visit the near child when tp + slack(tp) >= tmin. That
// puts the slack's multiply and add between the plane distance and the choice of the next
// node, on the one dependency chain a descent is made of. Instead each interval bound is
// stored already widened by wide(t) = 3 slack(t), and the choice compares tp itself:
// near when tp >= tmin, far when tp <= tmax; the slack is computed beside the chain, for
// the children's bounds only. This visits every cell the rule above visits and stops no
// sooner (with r = the relative slack, below 1/3: tp < tp0 - 3 slack(tp0) implies
// tp + slack(tp) < tp0 - (2 - 3r) slack(tp0) <= tp0 - slack(tp0), and the same mirrored;
// a stored entry tp - 3 slack(tp) lies below the old entry tp - slack(tp) less its own
// slack, so "skip when best < entry" skips no cell the old rule would enter).
template <typename Real>
struct TravRay {
  Real org[3];
  Real inv_dir[3];
  bool parallel[3];
  std::uint32_t negative[3];  // 1 when the right child comes first
  Real wide_abs;               // 3 * abs_slack

  Real wide(Real t) const { return (t < Real(0) ? -t : t) * Real(3 * kKdRelativeSlack) + wide_abs; }
};

template <typename Real>
struct StackEntry {
  std::uint32_t node;
  Real tmin, tmax;
};

template <typename Real>
inline TravRay<Real> make_trav_ray(const Ray& ray, const KdRaySetup& s, Real& tmin, Real& tmax) {
  TravRay<Real> tr;
  const float org[3] = {ray.org.x, ray.org.y, ray.org.z};
  for (int a = 0; a < 3; ++a) {
    tr.org[a] = org[a];
    tr.parallel[a] = s.parallel[a];
    tr.negative[a] = s.negative[a] ? 1u : 0u;
    if constexpr (std::is_same_v<Real, float>) {
      tr.inv_dir[a] = s.inv_dir_f[a];
    } else {
      tr.inv_dir[a] = s.inv_dir[a];
    }
  }
  if constexpr (std::is_same_v<Real, float>) {
    tr.wide_abs = 3.0f * s.abs_slack_f;
    tmin = s.t0_f;
    tmax = s.t1_f;
  } else {
    tr.wide_abs = 3.0 * s.abs_slack;
    tmin = s.t0;
    tmax = s.t1;
  }
  // The root interval in the stored (wide) form.
  tmin -= tr.wide(tmin);
  tmax += tr.wide(tmax);
  return tr;
}

// How descend() picks the cells: with selects (Select, for closest-hit rays: which cells
// a bounce ray's interval overlaps is close to a coin toss) or with branches (Branch, for
// any-hit rays, which the renderer and the benchmarks send toward a light from neighbouring
// points: there the branches are predicted, and the select form was 17-25 % slower on the
// shadow sets of balls-3, rings-5 and nefertiti, one thread, AVX-512).
enum class StepForm { Select, Branch };

// Moves from an inner node to the child (or children) the ray's interval overlaps.
// Returns the node to visit next and narrows [tmin, tmax]; pushes the far child when both
// are visited. Both forms visit the same cells in the same order. The bounds are in the
// wide form (TravRay): the choice reads tp alone, the slack only the children's bounds.
template <StepForm Form, typename Real>
inline std::uint32_t descend(NodeWords n, const TravRay<Real>& tr, Real& tmin, Real& tmax, StackEntry<Real>* stack,
                             int& sp) {
  const std::uint32_t a = n.flags_offset & 3u;
  const Real split = bits_to_float(n.bits);
  const std::uint32_t left = n.flags_offset >> 2;
  if (tr.parallel[a]) {
    if (tr.org[a] < split) return left;
    if (tr.org[a] > split) return left + 1;
    stack[sp++] = {left + 1, tmin, tmax};  // lies in the plane: both cells
    return left;
  }
  const Real tp = (split - tr.org[a]) * tr.inv_dir[a];
  const std::uint32_t first = left + tr.negative[a];
  const std::uint32_t second = left + 1 - tr.negative[a];
  const bool visit_first = tp >= tmin;
  const bool visit_second = tp <= tmax;
  const Real w = tr.wide(tp);
  const Real lo = tp - w, hi = tp + w;
  if constexpr (Form == StepForm::Branch) {
    if (visit_first && visit_second) {
      stack[sp++] = {second, lo > tmin ? lo : tmin, tmax};
      if (hi < tmax) tmax = hi;
      return first;
    }
    if (visit_first) {
      if (hi < tmax) tmax = hi;
      return first;
    }
    if (lo > tmin) tmin = lo;
    return second;
  }
  // Select form: the far cell's entry is always written and kept only when both cells are
  // visited (at least one always is: tmin <= tmax).
  const Real far_min = lo > tmin ? lo : tmin;
  const Real near_max = hi < tmax ? hi : tmax;
  stack[sp] = {second, far_min, tmax};
  sp += int(visit_first & visit_second);
  tmin = visit_first ? tmin : far_min;
  tmax = visit_first ? near_max : tmax;
  return visit_first ? first : second;
}

// The watertight kernel's per-ray constants (WatertightRay, the same permutation and
// shear), broadcast to N lanes; rows are the float offsets in a block of the vertex rows of
// the sheared x, y and z axes (the block holds x[3][B], y[3][B], z[3][B]).
template <int N>
struct LeafRay {
  vfloat<N> ox, oy, oz;  // origin in sheared axis order (kx, ky, kz)
  vfloat<N> sx, sy, sz;
  vfloat<N> tnear;
  std::uint32_t row_x, row_y, row_z;
};

// The float offsets in a block of B lanes of the vertex rows of the sheared axes kx, ky,
// kz, for the permutation (kz, swapped) of WatertightRay (kd_ray_setup-inl.h).
template <int B>
inline void shear_rows(int kz, bool swapped, std::uint32_t rows[3]) {
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (swapped) {
    const int k = kx;
    kx = ky;
    ky = k;
  }
  rows[0] = static_cast<std::uint32_t>(3 * B * kx);
  rows[1] = static_cast<std::uint32_t>(3 * B * ky);
  rows[2] = static_cast<std::uint32_t>(3 * B * kz);
}

template <int N, int B>
inline LeafRay<N> make_leaf_ray(const Ray& r) {
  const float d[3] = {r.dir.x, r.dir.y, r.dir.z}, o[3] = {r.org.x, r.org.y, r.org.z};
  const kdr::ShearLanes<1> sh = kdr::shear_lanes<1>(o, d);  // the packets' routine at width 1
  LeafRay<N> lr;
  lr.ox = vfloat<N>(sh.sorg[0]);
  lr.oy = vfloat<N>(sh.sorg[1]);
  lr.oz = vfloat<N>(sh.sorg[2]);
  lr.sx = vfloat<N>(sh.shear[0]);
  lr.sy = vfloat<N>(sh.shear[1]);
  lr.sz = vfloat<N>(sh.shear[2]);
  lr.tnear = vfloat<N>(r.tnear);
  std::uint32_t rows[3];
  shear_rows<B>(sh.kz[0] ? 0 : (sh.kz[1] ? 1 : 2), sh.swapped, rows);
  lr.row_x = rows[0], lr.row_y = rows[1], lr.row_z = rows[2];
  return lr;
}

// What one vector test leaves for the caller: lanes hit with tnear <= t < limit, and lanes
// with an edge function exactly 0 (to be redone by the scalar kernel).
template <int N>
struct LaneTest {
  int hit_bits;
  int zero_bits;
  vfloat<N> t, V, W, det;
};

// The watertight test (watertight.h's operations in its order) of vertices A, B, C already
// relative to the ray origins, in the sheared axis order, with the shear constants sx, sy,
// sz: for N triangles and one ray, N rays and one triangle, or N pairs. With EarlyOut, the
// division is skipped (and nothing reported) when no lane of `live` can hit: the lanes
// that would be reported are the same.
template <int N, bool EarlyOut = false>
__attribute__((always_inline)) inline LaneTest<N> test_relative(vfloat<N> Ax, vfloat<N> Ay, vfloat<N> Az,
                                                                vfloat<N> Bx, vfloat<N> By, vfloat<N> Bz,
                                                                vfloat<N> Cx, vfloat<N> Cy, vfloat<N> Cz,
                                                                vfloat<N> sx, vfloat<N> sy, vfloat<N> sz,
                                                                vfloat<N> tnear, vfloat<N> limit, int live = -1) {
  const vfloat<N> ax = Ax - sx * Az, ay = Ay - sy * Az;
  const vfloat<N> bx = Bx - sx * Bz, by = By - sy * Bz;
  const vfloat<N> cx = Cx - sx * Cz, cy = Cy - sy * Cz;

  LaneTest<N> out;
  const vfloat<N> U = cx * by - cy * bx;
  out.V = ax * cy - ay * cx;
  out.W = bx * ay - by * ax;
  const vfloat<N> zero(0.0f);
  const vbool<N> is_zero = (U == zero) | (out.V == zero) | (out.W == zero);
  const vbool<N> negative = (U < zero) | (out.V < zero) | (out.W < zero);
  const vbool<N> positive = (U > zero) | (out.V > zero) | (out.W > zero);
  const vbool<N> mixed_signs = negative & positive;
  out.zero_bits = movemask(is_zero) & live;
  if constexpr (EarlyOut) {
    // Most rays miss most triangles: skip the (exact, slow) division when no lane can hit.
    if (((~movemask(mixed_signs) & live) | out.zero_bits) == 0) {
      out.hit_bits = 0;
      return out;
    }
  }
  out.det = U + out.V + out.W;
  const vfloat<N> az = sz * Az, bz = sz * Bz, cz = sz * Cz;
  const vfloat<N> T = U * az + out.V * bz + out.W * cz;
  out.t = T / out.det;
  // det != 0 is true for NaN, whose t is NaN and fails the range test (padding lanes).
  const vbool<N> in_range = (out.t >= tnear) & (out.t < limit) & (out.det != zero);
  out.hit_bits = movemask(andnot(andnot(in_range, mixed_signs), is_zero)) & live;
  return out;
}

// Watertight test of N consecutive slots (`lanes` points at lane 0 of the x row of vertex
// 0 in their block), in watertight.h's order of operations.
template <int N, int B, bool EarlyOut = false>
inline LaneTest<N> test_lanes(const float* lanes, const LeafRay<N>& r, vfloat<N> limit) {
  const Lanes<N> w;
  const vfloat<N> Ax = load(w, lanes + r.row_x) - r.ox, Ay = load(w, lanes + r.row_y) - r.oy;
  const vfloat<N> Az = load(w, lanes + r.row_z) - r.oz;
  const vfloat<N> Bx = load(w, lanes + r.row_x + B) - r.ox, By = load(w, lanes + r.row_y + B) - r.oy;
  const vfloat<N> Bz = load(w, lanes + r.row_z + B) - r.oz;
  const vfloat<N> Cx = load(w, lanes + r.row_x + 2 * B) - r.ox, Cy = load(w, lanes + r.row_y + 2 * B) - r.oy;
  const vfloat<N> Cz = load(w, lanes + r.row_z + 2 * B) - r.oz;
  return test_relative<N, EarlyOut>(Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz, r.sx, r.sy, r.sz, r.tnear, limit);
}

// Counting hooks: NoCounts compiles to nothing.
struct NoCounts {
  void step() {}
  void leaf() {}
  void tests(std::uint32_t) {}
};
struct Counting {
  KdTraversalCounts* c;
  void step() { ++c->inner_steps; }
  void leaf() { ++c->leaves; }
  void tests(std::uint32_t n) { c->triangle_tests += n; }
};

inline Hit miss() { return Hit{kInfinity, kNoHit, 0.0f, 0.0f}; }

template <int N, int B, typename Real, typename Counter>
Hit closest(const KdTreeView& tree, const Ray& ray, const KdRaySetup& setup, Counter counter) {
  Real tmin, tmax;
  const TravRay<Real> tr = make_trav_ray<Real>(ray, setup, tmin, tmax);
  const LeafRay<N> lr = make_leaf_ray<N, B>(ray);
  // The best hit so far; with none, best_t = tfar and best_prim = kNoHit, so the rule
  // below accepts any hit (the kernel only reports t < tfar).
  float best_t = ray.tfar, best_u = 0.0f, best_v = 0.0f;
  std::uint32_t best_prim = kNoHit;
  float limit = ray.tfar;  // next_up(best_t) once there is a hit: accepts t == best_t
  StackEntry<Real> stack[kKdStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  for (;;) {
    NodeWords n = read_node(tree.nodes, node);
    while ((n.flags_offset & 3u) != KdNode::kLeafFlag) {
      counter.step();
      node = descend<StepForm::Select>(n, tr, tmin, tmax, stack, sp);
      n = read_node(tree.nodes, node);
    }
    counter.leaf();
    const std::uint32_t first = n.flags_offset >> 2, end = first + n.bits;
    for (std::uint32_t slot = first; slot < end; slot += N) {
      counter.tests(end - slot < std::uint32_t(N) ? end - slot : std::uint32_t(N));
      const float* lanes = tree.blocks + std::size_t(slot / B) * (9 * B) + slot % B;
      const LaneTest<N> lt = test_lanes<N, B, true>(lanes, lr, vfloat<N>(limit));
      int todo = lt.hit_bits | lt.zero_bits;
      if (todo == 0) continue;
      alignas(64) float ts[N], vs[N], ws[N], dets[N];
      store(ts, lt.t);
      store(vs, lt.V);
      store(ws, lt.W);
      store(dets, lt.det);
      for (; todo != 0; todo &= todo - 1) {  // lanes in ascending slot order
        const int l = __builtin_ctz(static_cast<unsigned>(todo));
        const std::uint32_t prim = tree.prims[slot + l];
        float t, u, v;
        if ((lt.zero_bits >> l) & 1) {
          float tuv[3];
          if (!kd_slot_hit(tree, ray, slot + l, limit, tuv)) continue;
          t = tuv[0], u = tuv[1], v = tuv[2];
        } else {
          t = ts[l];
          const float inv = 1.0f / dets[l];
          u = vs[l] * inv;
          v = ws[l] * inv;
        }
        if (t < best_t || (t == best_t && prim < best_prim)) {
          best_t = t, best_u = u, best_v = v, best_prim = prim;
          limit = next_up(t);
        }
      }
    }
    // Next cell on the stack that can still hold a hit at or before best_t.
    for (;;) {
      if (sp == 0) return best_prim == kNoHit ? miss() : Hit{best_t, best_prim, best_u, best_v};
      const StackEntry<Real>& e = stack[--sp];
      if (Real(best_t) < e.tmin) continue;  // e.tmin is wide: already less its slack
      node = e.node;
      tmin = e.tmin;
      tmax = e.tmax;
      break;
    }
  }
}

template <int N, int B, typename Real, typename Counter>
bool any_hit(const KdTreeView& tree, const Ray& ray, const KdRaySetup& setup, Counter counter) {
  Real tmin, tmax;
  const TravRay<Real> tr = make_trav_ray<Real>(ray, setup, tmin, tmax);
  const LeafRay<N> lr = make_leaf_ray<N, B>(ray);
  const vfloat<N> limit(ray.tfar);
  StackEntry<Real> stack[kKdStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  for (;;) {
    NodeWords n = read_node(tree.nodes, node);
    while ((n.flags_offset & 3u) != KdNode::kLeafFlag) {
      counter.step();
      node = descend<StepForm::Branch>(n, tr, tmin, tmax, stack, sp);
      n = read_node(tree.nodes, node);
    }
    counter.leaf();
    const std::uint32_t first = n.flags_offset >> 2, end = first + n.bits;
    for (std::uint32_t slot = first; slot < end; slot += N) {
      counter.tests(end - slot < std::uint32_t(N) ? end - slot : std::uint32_t(N));
      const float* lanes = tree.blocks + std::size_t(slot / B) * (9 * B) + slot % B;
      const LaneTest<N> lt = test_lanes<N, B, true>(lanes, lr, limit);
      if (lt.hit_bits != 0) return true;
      for (int todo = lt.zero_bits; todo != 0; todo &= todo - 1) {
        float tuv[3];
        if (kd_slot_hit(tree, ray, slot + __builtin_ctz(static_cast<unsigned>(todo)), ray.tfar, tuv)) return true;
      }
    }
    if (sp == 0) return false;
    const StackEntry<Real>& e = stack[--sp];
    node = e.node;
    tmin = e.tmin;
    tmax = e.tmax;
  }
}

// The common case of one ray's setup: the packets' width-generic routine at width 1
// (kd_ray_setup-inl.h). Fills s (plan Traverse with float_ok, or Miss) and returns true,
// or returns false for a ray it declines (kd_setup_ray_double then takes it).
inline bool setup_float(const KdTreeView& tree, const Ray& ray, KdRaySetup& s) {
  if (tree.bounds.empty()) return false;
  const float org[3] = {ray.org.x, ray.org.y, ray.org.z}, dir[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  const kdr::ClipLanes<1> c = kdr::clip_lanes<1>(tree, org, dir, ray.tnear, ray.tfar, true);
  if (!c.ok) return false;
  s.plan = c.inside ? KdPlan::Traverse : KdPlan::Miss;
  s.float_ok = true;
  for (int a = 0; a < 3; ++a) {
    s.parallel[a] = false;
    s.negative[a] = dir[a] < 0.0f;
    s.inv_dir_f[a] = c.inv[a];
  }
  s.abs_slack_f = c.abs_slack;
  s.t0_f = c.t0;
  s.t1_f = c.t1;
  return true;
}

inline KdRaySetup setup(const KdTreeView& tree, const Ray& ray) {
  KdRaySetup s{};
  if (!setup_float(tree, ray, s)) s = kd_setup_ray_double(tree, ray);
  return s;
}

template <int N, int B, typename Counter>
Hit intersect_with(const KdTreeView& tree, const Ray& ray, Counter counter) {
  const KdRaySetup s = setup(tree, ray);
  if (s.plan == KdPlan::Miss) return miss();
  if (s.plan == KdPlan::Scan) return kd_scan_intersect(tree, ray);
  return s.float_ok ? closest<N, B, float>(tree, ray, s, counter) : closest<N, B, double>(tree, ray, s, counter);
}

template <int N, int B, typename Counter>
bool occluded_with(const KdTreeView& tree, const Ray& ray, Counter counter) {
  static_assert(B % N == 0, "a vector covers lanes of one block");
  const KdRaySetup s = setup(tree, ray);
  if (s.plan == KdPlan::Miss) return false;
  if (s.plan == KdPlan::Scan) return kd_scan_occluded(tree, ray);
  return s.float_ok ? any_hit<N, B, float>(tree, ray, s, counter) : any_hit<N, B, double>(tree, ray, s, counter);
}

}  // namespace kd

// The single-ray entry points of one ISA's table (KdKernels). The tree's blocks must be B wide.
template <int N, int B>
Hit kd_intersect(const KdTreeView& tree, const Ray& ray) {
  return kd::intersect_with<N, B>(tree, ray, kd::NoCounts{});
}

template <int N, int B>
Hit kd_intersect_counted(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts) {
  return kd::intersect_with<N, B>(tree, ray, kd::Counting{&counts});
}

template <int N, int B>
bool kd_occluded(const KdTreeView& tree, const Ray& ray) {
  return kd::occluded_with<N, B>(tree, ray, kd::NoCounts{});
}

template <int N, int B>
bool kd_occluded_counted(const KdTreeView& tree, const Ray& ray, KdTraversalCounts& counts) {
  return kd::occluded_with<N, B>(tree, ray, kd::Counting{&counts});
}

}  // namespace lancer::LANCER_ISA
