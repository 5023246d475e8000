// Packet kd-tree traversal: up to 64 rays descend the tree together (Wald, Slusallek,
// Benthin & Wagner, "Interactive Rendering with Coherent Ray Tracing", EG 2001; Wald's
// thesis, 2004, ch. 7), as templates over the vector width N and the leaf block width B,
// compiled once per ISA inside namespace lancer::LANCER_ISA (kd_traverse_<isa>.cpp).
// Written from scratch.
//
// Layout: the rays are converted to SoA on entry, 64 / N vectors of N lanes. One shared
// stack; an entry holds a node, a 64-bit active mask and every ray's [tmin, tmax]. At an
// inner node each active lane computes exactly what single-ray descend() computes (same
// float operations, same slack), which gives the lanes that need the left and the right
// child and their narrowed intervals; a child is skipped only when no active lane needs it.
// Lanes whose direction sign on the split axis differs from the packet's majority are
// handled in place: per lane, near/far map to left/right by its own sign (a select), and
// the packet visits the children in the majority's order. Visiting a lane's far child
// first costs work, never exactness: the closest hit is the minimum of (t, triangle index)
// over every candidate found, whatever the order, and a lane drops an entry only when
// best_t < entry tmin - slack(tmin) (the single-ray stopping rule).
//
// Leaves: with one shared origin (camera packets) the packet's frustum first culls the
// leaf's triangles no lane can hit, exactly (frustum_keep). Each remaining triangle is
// broadcast and tested against all active rays at once, with
// kd_traverse-inl.h's test (watertight.h's operations in its order, no FMA: the build
// passes -ffp-contract=off), zero edge functions redone by the scalar kernel. The shear
// permutation (kx, ky, kz and the swap when dir[kz] < 0) differs per ray, so the rays are
// split into up to six classes by permutation, each traversed as its own packet (camera
// packets nearly always form one class). So every lane sees the very arithmetic of the
// single-ray kernel on every leaf that the single-ray traversal visits (and possibly more),
// and the answers equal the oracle's bit for bit.
//
// Setup: kd_packet_setup-inl.h, N rays at a time in float. Rays it leaves (axis-parallel,
// extreme or non-finite) take kd_setup_ray_double; those the single-ray kernel does not traverse
// in float (miss, scan or double plans, see kd_traverse-inl.h) are answered by it one by
// one.
#pragma once

#include "simd/isa_namespace.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include "accel/kd_traverse-inl.h"
#include "accel/kd_packet_setup-inl.h"

namespace lancer::LANCER_ISA {
namespace kdp {

using kd::bits_to_float;
using kd::next_up;
using kd::NodeWords;
using kd::read_node;

struct alignas(64) PacketEntry {
  float tmin[kMaxPacket];
  float tmax[kMaxPacket];
  std::uint32_t node;
  std::uint64_t active;
};

template <int N>
inline std::uint32_t lane_bits(std::uint64_t mask, int v) {
  constexpr std::uint64_t kLaneMask = N == 64 ? ~0ull : (1ull << N) - 1;
  return static_cast<std::uint32_t>((mask >> (v * N)) & kLaneMask);
}

inline int popcount64(std::uint64_t m) { return __builtin_popcountll(m); }

// select for masks: m ? a : b, lane by lane.
template <typename Mask>
inline Mask select_bool(Mask m, Mask a, Mask b) {
  return (m & a) | andnot(b, m);
}

// Splits the parent's lanes (entries[c]) at an inner node: the first child's intervals go
// to entries[c + 1], the second's back to entries[c]. Returns the first child's node and
// sets the two masks.
template <int N, bool SameOrigin>
inline std::uint32_t split_lanes(NodeWords n, const PacketRays& p, const PacketEntry& parent, PacketEntry& second_out,
                                 PacketEntry& first_out, int nvec, std::uint64_t& first_mask,
                                 std::uint64_t& second_mask) {
  const Lanes<N> w;
  const std::uint32_t a = n.flags_offset & 3u;
  const float split_f = bits_to_float(n.bits);
  const std::uint32_t left = n.flags_offset >> 2;
  const std::uint64_t active = parent.active;
  const std::uint64_t negative = p.negative[a] & active;
  if ((p.parallel[a] & active) == 0 && (negative == 0 || negative == active)) {
    // The usual case in a coherent packet: every lane crosses the plane in the same
    // direction, so near is the same child for all; the same arithmetic as below. The far
    // child's intervals go back to the parent's entry (only tmin changes).
    const vfloat<N> rel(static_cast<float>(kKdRelativeSlack));
    std::uint64_t near_mask = 0, far_mask = 0;
    for (int v = 0; v < nvec; ++v) {
      const std::uint32_t m = lane_bits<N>(active, v);
      if (m == 0) continue;
      const int o = v * N;
      const vfloat<N> tmin = load(w, parent.tmin + o), tmax = load(w, parent.tmax + o);
      const vfloat<N> distance = SameOrigin ? vfloat<N>(split_f - p.org[a][__builtin_ctzll(active)])
                                            : vfloat<N>(split_f) - load(w, p.org[a] + o);
      const vfloat<N> tp = distance * load(w, p.inv_dir[a] + o);
      const vfloat<N> s = abs(tp) * rel + load(w, p.abs_slack + o);
      const vfloat<N> hi = tp + s, lo = tp - s;
      store(first_out.tmin + o, tmin);
      store(first_out.tmax + o, select(hi < tmax, hi, tmax));
      store(second_out.tmin + o, select(lo > tmin, lo, tmin));
      near_mask |= std::uint64_t(static_cast<std::uint32_t>(movemask(hi >= tmin)) & m) << o;
      far_mask |= std::uint64_t(static_cast<std::uint32_t>(movemask(lo <= tmax)) & m) << o;
    }
    first_mask = near_mask;
    second_mask = far_mask;
    return negative != 0 ? left + 1 : left;
  }
  // The packet's order: the majority of the active lanes' near child first.
  const bool right_first = 2 * popcount64(p.negative[a] & active) > popcount64(active);
  const vfloat<N> split(split_f), rel(static_cast<float>(kKdRelativeSlack));
  std::uint64_t left_mask = 0, right_mask = 0;
  PacketEntry& L = right_first ? second_out : first_out;
  PacketEntry& R = right_first ? first_out : second_out;
  for (int v = 0; v < nvec; ++v) {
    const std::uint32_t m = lane_bits<N>(active, v);
    if (m == 0) continue;
    const int o = v * N;
    const vfloat<N> tmin = load(w, parent.tmin + o), tmax = load(w, parent.tmax + o);
    const vfloat<N> org = load(w, p.org[a] + o);
    const vfloat<N> tp = (split - org) * load(w, p.inv_dir[a] + o);
    const vfloat<N> s = abs(tp) * rel + load(w, p.abs_slack + o);
    const vfloat<N> hi = tp + s, lo = tp - s;
    const vbool<N> near_ok = hi >= tmin, far_ok = lo <= tmax;
    const vfloat<N> near_tmax = select(hi < tmax, hi, tmax), far_tmin = select(lo > tmin, lo, tmin);
    const vbool<N> par = mask_from_bits(w, static_cast<int>(lane_bits<N>(p.parallel[a], v)));
    const vbool<N> neg = mask_from_bits(w, static_cast<int>(lane_bits<N>(p.negative[a], v)));
    // A lane parallel to the plane keeps its interval: left when org <= split, right when
    // org >= split (both when it lies in the plane).
    const vbool<N> left_ok = select_bool(par, !(org > split), select_bool(neg, far_ok, near_ok));
    const vbool<N> right_ok = select_bool(par, !(org < split), select_bool(neg, near_ok, far_ok));
    const vbool<N> neg_moving = andnot(neg, par), pos_moving = andnot(!neg, par);
    store(L.tmin + o, select(neg_moving, far_tmin, tmin));
    store(L.tmax + o, select(pos_moving, near_tmax, tmax));
    store(R.tmin + o, select(pos_moving, far_tmin, tmin));
    store(R.tmax + o, select(neg_moving, near_tmax, tmax));
    left_mask |= std::uint64_t(static_cast<std::uint32_t>(movemask(left_ok)) & m) << o;
    right_mask |= std::uint64_t(static_cast<std::uint32_t>(movemask(right_ok)) & m) << o;
  }
  first_mask = right_first ? right_mask : left_mask;
  second_mask = right_first ? left_mask : right_mask;
  return right_first ? left + 1 : left;
}

// Lane i's closest hit by the oracle's rule: smaller t, or equal t and a lower triangle
// index (so the order of the tests does not matter). V, W, det as in PacketRays.
//
// For occlusion any hit will do: it sets best_t and limit to -inf, so that no later test
// of the lane can hit (t < limit fails) and the lane drops every pending cell when the
// next one is popped (best_t < entry); a packet whose lanes are all done unwinds its stack.
inline void keep_closest(PacketRays& p, int i, float t, float V, float W, float det, std::uint32_t prim) {
  if (p.any_hit) {
    p.best_t[i] = p.limit[i] = -__builtin_inff();
    p.best_prim[i] = prim;
    return;
  }
  if (t < p.best_t[i] || (t == p.best_t[i] && prim < p.best_prim[i])) {
    p.best_t[i] = t, p.best_V[i] = V, p.best_W[i] = W, p.best_det[i] = det, p.best_prim[i] = prim;
    p.limit[i] = next_up(t);
  }
}

// keep_closest for the lanes `hit` of the vector at offset o, all with triangle prim:
// masked stores instead of a scalar loop over the lanes.
template <int N>
inline void keep_closest_lanes(PacketRays& p, int o, vbool<N> hit, vfloat<N> t, vfloat<N> V, vfloat<N> W,
                               vfloat<N> det, std::uint32_t prim) {
  const Lanes<N> w;
  std::int32_t* best_prim = reinterpret_cast<std::int32_t*>(p.best_prim) + o;
  if (p.any_hit) {  // keep_closest's occlusion rule
    const vfloat<N> done(-__builtin_inff());
    store(hit, p.best_t + o, done);
    store(hit, p.limit + o, done);
    store(hit, best_prim, vint<N>(static_cast<std::int32_t>(prim)));
    return;
  }
  const vfloat<N> zero(0.0f), best = load(w, p.best_t + o);
  // Unsigned order of triangle indices through signed compares (kNoHit is the largest).
  const vint<N> bias(std::numeric_limits<std::int32_t>::min()), id(static_cast<std::int32_t>(prim));
  const vbool<N> lower = (id ^ bias) < (load(w, best_prim) ^ bias);
  const vbool<N> closer = hit & ((t < best) | ((t == best) & lower));
  // next_up(t), as kd::next_up: one ulp towards +inf, the least subnormal above a zero.
  // On the magnitude's bits, so that no lane's integer step can overflow (-0 is INT_MIN).
  const vint<N> mag = as_int(abs(t)), one(1);
  const vfloat<N> up =
      select(t > zero, as_float(mag + one), select(t < zero, -as_float(mag - one), vfloat<N>(0x1p-149f)));
  store(closer, p.best_t + o, t);
  store(closer, p.limit + o, up);
  store(closer, p.best_V + o, V);
  store(closer, p.best_W + o, W);
  store(closer, p.best_det + o, det);
  store(closer, best_prim, id);
}

// The watertight test of one triangle (A, B, C: its vertices minus the ray origins, in
// the sheared axis order) against the lanes m of vector v, keeping each lane's closest.
template <int N>
__attribute__((always_inline)) inline void test_triangle(const KdTreeView& tree, const Ray* rays, PacketRays& p,
                                                         std::uint32_t slot, int v, std::uint32_t m, vfloat<N> Ax,
                                                         vfloat<N> Ay, vfloat<N> Az, vfloat<N> Bx, vfloat<N> By,
                                                         vfloat<N> Bz, vfloat<N> Cx, vfloat<N> Cy, vfloat<N> Cz) {
  const Lanes<N> w;
  const int o = v * N;
  const kd::LaneTest<N> lt = kd::test_relative<N, true>(
      Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz, load(w, p.shear[0] + o), load(w, p.shear[1] + o), load(w, p.shear[2] + o),
      load(w, p.tnear + o), load(w, p.limit + o), static_cast<int>(m));
  if (lt.hit_bits != 0)
    keep_closest_lanes<N>(p, o, mask_from_bits(w, lt.hit_bits), lt.t, lt.V, lt.W, lt.det,
                          tree.prims[slot]);  // a leaf's [begin, end) holds no padding
  for (int todo = lt.zero_bits; todo != 0; todo &= todo - 1) {
    const int i = o + __builtin_ctz(static_cast<unsigned>(todo));
    float tuv[3];
    if (kd_slot_hit(tree, rays[i], slot, p.limit[i], tuv)) keep_closest(p, i, tuv[0], tuv[1], tuv[2], 1.0f, tree.prims[slot]);
  }
}

// Lane i's hits among a vector test of N triangles from `slot` (keep_closest for each).
template <int N>
__attribute__((always_inline)) inline void keep_lane_hits(const KdTreeView& tree, const Ray* rays, PacketRays& p,
                                                          int i, std::uint32_t slot, const kd::LaneTest<N>& lt) {
  int todo = lt.hit_bits | lt.zero_bits;
  if (todo == 0) return;
  alignas(64) float ts[N], vs[N], ws[N], dets[N];
  store(ts, lt.t);
  store(vs, lt.V);
  store(ws, lt.W);
  store(dets, lt.det);
  for (; todo != 0; todo &= todo - 1) {
    const int l = __builtin_ctz(static_cast<unsigned>(todo));
    const std::uint32_t prim = tree.prims[slot + l];
    if ((lt.zero_bits >> l) & 1) {
      float tuv[3];
      if (kd_slot_hit(tree, rays[i], slot + l, p.limit[i], tuv)) keep_closest(p, i, tuv[0], tuv[1], tuv[2], 1.0f, prim);
    } else {
      keep_closest(p, i, ts[l], vs[l], ws[l], dets[l], prim);
    }
  }
}

// The range of the shear constants sx, sy over the lanes of a packet whose rays share one
// origin: its frustum in the sheared frame.
struct Frustum {
  float sx_lo, sx_hi, sy_lo, sy_hi;
};

template <int N>
inline Frustum frustum_of(const PacketRays& p, std::uint64_t active, int nvec) {
  const Lanes<N> w;
  const vfloat<N> inf(__builtin_inff()), minus_inf(-__builtin_inff());
  vfloat<N> sx_lo = inf, sx_hi = minus_inf, sy_lo = inf, sy_hi = minus_inf;
  for (int v = 0; v < nvec; ++v) {
    const std::uint32_t m = lane_bits<N>(active, v);
    if (m == 0) continue;
    const vbool<N> live = mask_from_bits(w, static_cast<int>(m));
    const vfloat<N> sx = load(w, p.shear[0] + v * N), sy = load(w, p.shear[1] + v * N);
    sx_lo = min(sx_lo, select(live, sx, inf));
    sx_hi = max(sx_hi, select(live, sx, minus_inf));
    sy_lo = min(sy_lo, select(live, sy, inf));
    sy_hi = max(sy_hi, select(live, sy, minus_inf));
  }
  // Reduced through memory: GCC 12's _mm512_reduce_min_ps warns of an uninitialised
  // value (a false positive in its header) when inlined here.
  alignas(64) float lanes[4][N];
  store(lanes[0], sx_lo), store(lanes[1], sx_hi), store(lanes[2], sy_lo), store(lanes[3], sy_hi);
  Frustum f{lanes[0][0], lanes[1][0], lanes[2][0], lanes[3][0]};
  for (int i = 1; i < N; ++i) {
    f.sx_lo = lanes[0][i] < f.sx_lo ? lanes[0][i] : f.sx_lo;
    f.sx_hi = lanes[1][i] > f.sx_hi ? lanes[1][i] : f.sx_hi;
    f.sy_lo = lanes[2][i] < f.sy_lo ? lanes[2][i] : f.sy_lo;
    f.sy_hi = lanes[3][i] > f.sy_hi ? lanes[3][i] : f.sy_hi;
  }
  return f;
}

// Of N triangles (vertices minus the shared origin, sheared axis order), those that some
// lane of the packet may hit, as bits. Exact, not a heuristic: test_triangle computes
// ax = Ax - sx * Az with two roundings, each monotone, so over the lanes' sx in
// [sx_lo, sx_hi] its largest value is the one at sx_lo when Az > 0 (sx_hi otherwise) and
// its smallest the other. When every lane sees all three vertices strictly on one side
// (ax < 0, say), the float triangle lies in an open half-plane without the ray's point,
// and the watertight test's edge functions (signs exact or zero, Woop et al. 2013) can
// only report a miss. Same for ay. NaN padding is never culled (the comparisons fail).
template <int N>
inline std::uint32_t frustum_keep(const Frustum& f, vfloat<N> Ax, vfloat<N> Ay, vfloat<N> Az, vfloat<N> Bx,
                                  vfloat<N> By, vfloat<N> Bz, vfloat<N> Cx, vfloat<N> Cy, vfloat<N> Cz) {
  const vfloat<N> zero(0.0f);
  const vfloat<N> xlo(f.sx_lo), xhi(f.sx_hi), ylo(f.sy_lo), yhi(f.sy_hi);
  const vbool<N> ap = Az > zero, bp = Bz > zero, cp = Cz > zero;
  // Each vertex's largest (hi) and smallest (lo) sheared x and y over the lanes. Named
  // first so that the width-1 case combines plain bools, never calls, with &.
  const vfloat<N> ax_hi = Ax - select(ap, xlo, xhi) * Az, ax_lo = Ax - select(ap, xhi, xlo) * Az;
  const vfloat<N> bx_hi = Bx - select(bp, xlo, xhi) * Bz, bx_lo = Bx - select(bp, xhi, xlo) * Bz;
  const vfloat<N> cx_hi = Cx - select(cp, xlo, xhi) * Cz, cx_lo = Cx - select(cp, xhi, xlo) * Cz;
  const vfloat<N> ay_hi = Ay - select(ap, ylo, yhi) * Az, ay_lo = Ay - select(ap, yhi, ylo) * Az;
  const vfloat<N> by_hi = By - select(bp, ylo, yhi) * Bz, by_lo = By - select(bp, yhi, ylo) * Bz;
  const vfloat<N> cy_hi = Cy - select(cp, ylo, yhi) * Cz, cy_lo = Cy - select(cp, yhi, ylo) * Cz;
  const vbool<N> ax_neg = ax_hi < zero, bx_neg = bx_hi < zero, cx_neg = cx_hi < zero;
  const vbool<N> ax_pos = ax_lo > zero, bx_pos = bx_lo > zero, cx_pos = cx_lo > zero;
  const vbool<N> ay_neg = ay_hi < zero, by_neg = by_hi < zero, cy_neg = cy_hi < zero;
  const vbool<N> ay_pos = ay_lo > zero, by_pos = by_lo > zero, cy_pos = cy_lo > zero;
  const vbool<N> left = ax_neg & bx_neg & cx_neg, right = ax_pos & bx_pos & cx_pos;
  const vbool<N> below = ay_neg & by_neg & cy_neg, above = ay_pos & by_pos & cy_pos;
  return ~static_cast<std::uint32_t>(movemask(left | right | below | above));
}

// True when the lanes in `mask` share one origin, bit for bit (a camera packet): then
// a - org is the same float for every lane and is computed once per triangle. Compared
// as integers, a vector at a time (every lane of a vector in use holds a value).
template <int N>
inline bool same_origin(const PacketRays& p, std::uint64_t mask, int nvec) {
  const Lanes<N> w;
  const int first = __builtin_ctzll(mask);
  for (int a = 0; a < 3; ++a) {
    const vint<N> ref(std::bit_cast<std::int32_t>(p.org[a][first]));
    for (int v = 0; v < nvec; ++v) {
      const std::uint32_t m = lane_bits<N>(mask, v);
      const std::uint32_t same = static_cast<std::uint32_t>(movemask(as_int(load(w, p.org[a] + v * N)) == ref));
      if ((same & m) != m) return false;
    }
  }
  return true;
}

// Ray i against the N slots from `slot` (one vector test; lanes past the leaf's end are
// NaN padding), with the single-ray kernel's test (test_lanes).
template <int N, int B>
__attribute__((always_inline)) inline void ray_vs_slots(const KdTreeView& tree, const Ray* rays, PacketRays& p, int i, std::uint32_t slot,
                         const std::uint32_t rows[3]) {
  kd::LeafRay<N> lr;
  lr.ox = vfloat<N>(p.sorg[0][i]), lr.oy = vfloat<N>(p.sorg[1][i]), lr.oz = vfloat<N>(p.sorg[2][i]);
  lr.sx = vfloat<N>(p.shear[0][i]), lr.sy = vfloat<N>(p.shear[1][i]), lr.sz = vfloat<N>(p.shear[2][i]);
  lr.tnear = vfloat<N>(p.tnear[i]);
  lr.row_x = rows[0], lr.row_y = rows[1], lr.row_z = rows[2];
  const float* lanes = tree.blocks + std::size_t(slot / B) * (9 * B) + slot % B;
  const kd::LaneTest<N> lt = kd::test_lanes<N, B>(lanes, lr, vfloat<N>(p.limit[i]));
  keep_lane_hits<N>(tree, rays, p, i, slot, lt);
}

// The leaf the other way round: each active ray against N triangles at a time. Cheaper
// than broadcasting triangles when few rays reach a big leaf (rays * ceil(n / N) vector
// tests instead of n * live vectors); the arithmetic per (ray, triangle) is the same, so
// the answers are too.
template <int N, int B>
inline void leaf_by_ray(const KdTreeView& tree, const Ray* rays, PacketRays& p, std::uint64_t active,
                        std::uint32_t begin, std::uint32_t end, const std::uint32_t rows[3]) {
  for (; active != 0; active &= active - 1) {
    const int i = __builtin_ctzll(active);
    for (std::uint32_t slot = begin; slot < end; slot += N) ray_vs_slots<N, B>(tree, rays, p, i, slot, rows);
  }
}

// The leaf for rays that share one origin (camera packets), N triangles at a time: the
// packet's frustum culls first; then per vector of rays, the cheaper of its live rays one
// by one against the N triangles (one vector test each) or the surviving triangles
// broadcast to its lanes (their a - org computed once, the same floats every lane would
// compute). Measured on the bunny's camera tiles (AVX-512, one thread, CPU time, best of
// 20), against no cull and the choice by triangle count: 23 -> 20 ns/ray at 1024 x 1024,
// 44 -> 46 ns/ray at 256 x 256 (wide packets cull less). Skipping the cull where little
// work is at stake did not win the 256 x 256 cost back; culling per vector of 16 rays as
// well cost more than it saved; the leaf tests must be inlined (not inlined: 10 %
// slower).
template <int N, int B>
inline void leaf_shared_origin(const KdTreeView& tree, const Ray* rays, PacketRays& p, const Frustum& f,
                               std::uint64_t active, int nvec, std::uint32_t begin, std::uint32_t end,
                               const std::uint32_t rows[3]) {
  const Lanes<N> w;
  const int first = __builtin_ctzll(active);
  const float ox = p.sorg[0][first], oy = p.sorg[1][first], oz = p.sorg[2][first];
  const vfloat<N> vox(ox), voy(oy), voz(oz);
  constexpr std::uint32_t kAll = N == 32 ? ~0u : (1u << N) - 1;
  // The slots of a leaf start on a block, so N-wide groups stay inside one block.
  for (std::uint32_t group = begin; group < end; group += N) {
    const float* base = tree.blocks + std::size_t(group / B) * (9 * B) + group % B;
    const vfloat<N> Ax = load(w, base + rows[0]) - vox, Ay = load(w, base + rows[1]) - voy;
    const vfloat<N> Az = load(w, base + rows[2]) - voz, Bx = load(w, base + rows[0] + B) - vox;
    const vfloat<N> By = load(w, base + rows[1] + B) - voy, Bz = load(w, base + rows[2] + B) - voz;
    const vfloat<N> Cx = load(w, base + rows[0] + 2 * B) - vox, Cy = load(w, base + rows[1] + 2 * B) - voy;
    const vfloat<N> Cz = load(w, base + rows[2] + 2 * B) - voz;
    const std::uint32_t valid = end - group >= std::uint32_t(N) ? kAll : (1u << (end - group)) - 1;
    const std::uint32_t keep = frustum_keep<N>(f, Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz) & valid;
    if (keep == 0) continue;
    const int kept = __builtin_popcount(keep);
    std::uint64_t broadcast = 0;  // bit v: vector v takes the kept triangles broadcast
    for (int v = 0; v < nvec; ++v) {
      std::uint32_t m = lane_bits<N>(active, v);
      if (m == 0) continue;
      if (__builtin_popcount(m) >= kept) {
        broadcast |= 1ull << v;
        continue;
      }
      // Ray by ray against the group's vertices already relative to the shared origin (the
      // same floats test_lanes would compute), only the kept triangles reported.
      for (; m != 0; m &= m - 1) {
        const int i = v * N + __builtin_ctz(m);
        const kd::LaneTest<N> lt = kd::test_relative<N, true>(
            Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz, vfloat<N>(p.shear[0][i]), vfloat<N>(p.shear[1][i]),
            vfloat<N>(p.shear[2][i]), vfloat<N>(p.tnear[i]), vfloat<N>(p.limit[i]), static_cast<int>(keep));
        keep_lane_hits<N>(tree, rays, p, i, group, lt);
      }
    }
    for (std::uint32_t todo_t = broadcast != 0 ? keep : 0; todo_t != 0; todo_t &= todo_t - 1) {
      const int l = __builtin_ctz(todo_t);
      const std::uint32_t slot = group + static_cast<std::uint32_t>(l);
      const float* t = base + l;
      const vfloat<N> ax(t[rows[0]] - ox), ay(t[rows[1]] - oy), az(t[rows[2]] - oz);
      const vfloat<N> bx(t[rows[0] + B] - ox), by(t[rows[1] + B] - oy), bz(t[rows[2] + B] - oz);
      const vfloat<N> cx(t[rows[0] + 2 * B] - ox), cy(t[rows[1] + 2 * B] - oy), cz(t[rows[2] + 2 * B] - oz);
      for (std::uint64_t todo = broadcast; todo != 0; todo &= todo - 1) {
        const int v = __builtin_ctzll(todo);
        test_triangle<N>(tree, rays, p, slot, v, lane_bits<N>(active, v), ax, ay, az, bx, by, bz, cx, cy, cz);
      }
    }
  }
}

// Tests the leaf's triangles (slots [begin, end)) against every active lane of the packet
// (one permutation class: rows give the block offsets of the sheared axes). Vectors with
// few live lanes go ray by ray (leaf_by_ray); the others get each triangle broadcast to
// their lanes, a vector of rays staying in registers while the triangles stream past it.
// Measured on the bunny's 256 x 256 camera tiles (AVX-512): the split per vector took
// packets from 2.1x to 3.0x the single-ray speed.
template <int N, int B>
inline void leaf_distinct_origins(const KdTreeView& tree, const Ray* rays, PacketRays& p, std::uint64_t active,
                                  int nvec, std::uint32_t begin, std::uint32_t end, const std::uint32_t rows[3]) {
  const std::uint32_t n = end - begin, tests_per_ray = (n + N - 1) / N;
  std::uint64_t by_ray = 0;
  for (int v = 0; v < nvec; ++v) {
    const std::uint32_t m = lane_bits<N>(active, v);
    if (m != 0 && static_cast<std::uint32_t>(__builtin_popcount(m)) * tests_per_ray < n)
      by_ray |= std::uint64_t(m) << (v * N);
  }
  if (by_ray != 0) {
    leaf_by_ray<N, B>(tree, rays, p, by_ray, begin, end, rows);
    active &= ~by_ray;
  }
  const Lanes<N> w;
  for (int v = 0; v < nvec; ++v) {
    const std::uint32_t m = lane_bits<N>(active, v);
    if (m == 0) continue;
    const int o = v * N;
    const vfloat<N> ox = load(w, p.sorg[0] + o), oy = load(w, p.sorg[1] + o), oz = load(w, p.sorg[2] + o);
    for (std::uint32_t slot = begin; slot < end; ++slot) {
      const float* base = tree.blocks + std::size_t(slot / B) * (9 * B) + slot % B;
      test_triangle<N>(tree, rays, p, slot, v, m, vfloat<N>(base[rows[0]]) - ox, vfloat<N>(base[rows[1]]) - oy,
                       vfloat<N>(base[rows[2]]) - oz, vfloat<N>(base[rows[0] + B]) - ox,
                       vfloat<N>(base[rows[1] + B]) - oy, vfloat<N>(base[rows[2] + B]) - oz,
                       vfloat<N>(base[rows[0] + 2 * B]) - ox, vfloat<N>(base[rows[1] + 2 * B]) - oy,
                       vfloat<N>(base[rows[2] + 2 * B]) - oz);
    }
  }
}

// One packet of rays that share a shear permutation (kz, swapped), starting with `active`.
template <int N, int B, bool SameOrigin>
void traverse_class(const KdTreeView& tree, const Ray* rays, PacketRays& p, std::uint64_t active, int nvec, int kz,
                    bool swapped) {
  const Lanes<N> w;
  std::uint32_t rows[3];
  kd::shear_rows<B>(kz, swapped, rows);
  // entries[c] is the current cell; entries below it are pending far cells (or dead ones
  // with no active lane). Depth <= kKdMaxDepth, so c + 1 < kKdStackSize.
  PacketEntry entries[kKdStackSize];
  int c = 0;
  entries[0].node = 0;
  std::memcpy(entries[0].tmin, p.t0, sizeof p.t0);
  std::memcpy(entries[0].tmax, p.t1, sizeof p.t1);
  entries[0].active = active;
  Frustum f{};
  if constexpr (SameOrigin) f = frustum_of<N>(p, active, nvec);
  const vfloat<N> rel(static_cast<float>(kKdRelativeSlack));
  for (;;) {
    NodeWords n = read_node(tree.nodes, entries[c].node);
    while ((n.flags_offset & 3u) != KdNode::kLeafFlag) {
      std::uint64_t first_mask, second_mask;
      const std::uint32_t first =
          split_lanes<N, SameOrigin>(n, p, entries[c], entries[c], entries[c + 1], nvec, first_mask, second_mask);
      const std::uint32_t second = (n.flags_offset >> 2) + ((n.flags_offset >> 2) + 1) - first;
      if (first_mask == 0) {  // the second child's intervals are already in entries[c]
        entries[c].node = second;
        entries[c].active = second_mask;
      } else {
        entries[c].node = second;
        entries[c].active = second_mask;  // 0: a dead entry, skipped when popped
        ++c;
        entries[c].node = first;
        entries[c].active = first_mask;
      }
      n = read_node(tree.nodes, entries[c].node);
    }
    const std::uint32_t begin = n.flags_offset >> 2, end = begin + n.bits;
    if constexpr (SameOrigin)
      leaf_shared_origin<N, B>(tree, rays, p, f, entries[c].active, nvec, begin, end, rows);
    else
      leaf_distinct_origins<N, B>(tree, rays, p, entries[c].active, nvec, begin, end, rows);
    // Next cell that some lane still needs: a lane drops it when its hit lies before the
    // cell's entry by more than the slack.
    for (;;) {
      if (c == 0) return;
      PacketEntry& e = entries[--c];
      std::uint64_t keep = e.active;
      for (int v = 0; v < nvec && keep != 0; ++v) {
        const std::uint32_t m = lane_bits<N>(e.active, v);
        if (m == 0) continue;
        const int o = v * N;
        const vfloat<N> tmin = load(w, e.tmin + o);
        const vfloat<N> entry = tmin - (abs(tmin) * rel + load(w, p.abs_slack + o));
        const std::uint32_t done = static_cast<std::uint32_t>(movemask(load(w, p.best_t + o) < entry)) & m;
        keep &= ~(std::uint64_t(done) << o);
      }
      if (keep == 0) continue;
      e.active = keep;
      break;
    }
  }
}

}  // namespace kdp

namespace kdp {

// Closest hits of rays[0..count) (count <= 64), each exactly KdTree::intersect's (and the
// oracle's), or with any_hit some hit of each ray that has one (hits[i].valid() exactly
// when KdTree::occluded is true; t, u, v are then meaningless). The tree's blocks must be
// B wide.
template <int N, int B>
void packet(const KdTreeView& tree, const Ray* rays, Hit* hits, int count, bool any_hit) {
  static_assert(B % N == 0 && kdp::kMaxPacket % N == 0, "vectors cover whole lanes");
  // Only the masks need zeroing: setup_vectors writes every lane of the vectors in use,
  // and lanes beyond them are never read (3.7 KiB of memset per packet otherwise).
  alignas(64) kdp::PacketRays p;
  p.any_hit = any_hit;
  for (int a = 0; a < 3; ++a) p.parallel[a] = p.negative[a] = 0;
  for (int k = 0; k < 6; ++k) p.klass[k] = 0;
  for (int i = 0; i < count; ++i) p.best_prim[i] = kNoHit;
  const kdp::SetupMasks masks = kdp::setup_vectors<N>(tree, rays, count, p, hits);
  std::uint64_t packet = masks.packet;
  // The lanes the vector setup left: kd_setup_ray_double's plans, as in single-ray traversal.
  for (std::uint64_t todo = masks.slow; todo != 0; todo &= todo - 1) {
    const int i = __builtin_ctzll(todo);
    const Ray& r = rays[i];
    const KdRaySetup s = kd_setup_ray_double(tree, r);  // the vector setup declined it
    if (s.plan == KdPlan::Miss) {
      hits[i] = kd::miss();
      continue;
    }
    if (s.plan == KdPlan::Scan) {
      hits[i] = kd_scan_intersect(tree, r);
      continue;
    }
    if (!s.float_ok) {
      hits[i] = kd::closest<N, B, double>(tree, r, s, kd::NoCounts{});
      continue;
    }
    const float d[3] = {r.dir.x, r.dir.y, r.dir.z}, o[3] = {r.org.x, r.org.y, r.org.z};
    for (int a = 0; a < 3; ++a) {
      p.org[a][i] = o[a];
      p.inv_dir[a][i] = s.inv_dir_f[a];
      if (s.parallel[a]) p.parallel[a] |= 1ull << i;
      if (s.negative[a]) p.negative[a] |= 1ull << i;
    }
    p.abs_slack[i] = s.abs_slack_f;
    p.t0[i] = s.t0_f;
    p.t1[i] = s.t1_f;
    p.tnear[i] = r.tnear;
    p.limit[i] = r.tfar;
    p.best_t[i] = r.tfar;
    p.best_det[i] = 1.0f;
    // WatertightRay's permutation and shear: the packets' own routine at width 1.
    const kdr::ShearLanes<1> sh = kdr::shear_lanes<1>(o, d);
    for (int k = 0; k < 3; ++k) {
      p.sorg[k][i] = sh.sorg[k];
      p.shear[k][i] = sh.shear[k];
      if (sh.kz[k]) p.klass[2 * k + (sh.swapped ? 1 : 0)] |= 1ull << i;
    }
    packet |= 1ull << i;
  }
  const int nvec = (count + N - 1) / N;
  for (int k = 0; k < 6; ++k) {
    if (p.klass[k] == 0) continue;
    if (kdp::same_origin<N>(p, p.klass[k], nvec))
      kdp::traverse_class<N, B, true>(tree, rays, p, p.klass[k], nvec, k / 2, (k & 1) != 0);
    else
      kdp::traverse_class<N, B, false>(tree, rays, p, p.klass[k], nvec, k / 2, (k & 1) != 0);
  }
  // u = V * (1 / det), v likewise: the single-ray kernel's operations, a vector at a time.
  const Lanes<N> w;
  alignas(64) float u[kdp::kMaxPacket], v[kdp::kMaxPacket];
  for (int k = 0; packet != 0 && k < nvec; ++k) {
    const int o = k * N;
    const vfloat<N> inv = vfloat<N>(1.0f) / load(w, p.best_det + o);
    store(u + o, load(w, p.best_V + o) * inv);
    store(v + o, load(w, p.best_W + o) * inv);
  }
  const auto write_hit = [&](int i) {
    const bool hit = p.best_prim[i] != kNoHit;  // branch-free: the compiler vectorises the full loop
    hits[i] = Hit{hit ? p.best_t[i] : kInfinity, p.best_prim[i], hit ? u[i] : 0.0f, hit ? v[i] : 0.0f};
  };
  if (count == kdp::kMaxPacket && packet == ~0ull) {
    for (int i = 0; i < kdp::kMaxPacket; ++i) write_hit(i);
  } else {
    for (std::uint64_t todo = packet; todo != 0; todo &= todo - 1) write_hit(__builtin_ctzll(todo));
  }
}

}  // namespace kdp

template <int N, int B>
void kd_intersect_packet(const KdTreeView& tree, const Ray* rays, Hit* hits, int count) {
  kdp::packet<N, B>(tree, rays, hits, count, false);
}

// occluded[i] = KdTree::occluded(rays[i]) for count <= 64 rays traversed as one packet,
// each lane leaving at its first hit (the slow lanes' closest hits answer the same).
template <int N, int B>
void kd_occluded_packet(const KdTreeView& tree, const Ray* rays, bool* occluded, int count) {
  Hit hits[kdp::kMaxPacket];
  kdp::packet<N, B>(tree, rays, hits, count, true);
  for (int i = 0; i < count; ++i) occluded[i] = hits[i].valid();
}

}  // namespace lancer::LANCER_ISA
