// Per-ray setup of a packet, N lanes at a time, in float (kd_packet-inl.h's first step).
// Compiled once per ISA inside namespace lancer::LANCER_ISA, like the traversal itself.
//
// kd_setup_ray (kd_traverse.cpp) decides each ray's plan one ray at a time; on coherent
// camera packets that (then in double) was a third of the packet's time. Here the same
// quantities are computed in float for a whole vector of rays, for the lanes where float is
// plainly safe: finite origin, direction and tnear, every direction component at least
// 2^-60, and the magnitudes kd_setup_ray's double path checks well inside its limits
// (E^2 max(E, D) / max|dir| within [2^-50, 2^90], abs_slack within [2^-90, 2^60], plane
// distances and the clipped interval below 2^60 and 2^64). Every other lane (axis-parallel,
// huge, tiny, NaN, infinite) takes kd_setup_ray and the single-ray paths as before, so the
// rare cases keep one careful implementation. kd_setup_ray_float is this same arithmetic
// for one ray, the single-ray traversal's common case.
//
// The float values differ from kd_setup_ray's rounded doubles by a few 2^-24 relative
// (1/dir, the box distances and the slack each round once more), which the 2^-20 term of
// kKdRelativeSlack is there to absorb (kd_traverse_setup.h); the interval stays a superset
// of the cells that can hold the oracle's answer, so the hits stay exact. A lane whose
// clipped interval is empty misses the widened scene box: nothing can hit it.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "accel/kd_traverse_setup.h"
#include "accel/ray.h"

namespace lancer::LANCER_ISA {
namespace kdp {

inline constexpr int kMaxPacket = 64;

// Per-ray data of one packet, SoA. Lanes of rays not in the packet are never read as
// active (their values are zero).
struct PacketRays {
  alignas(64) float org[3][kMaxPacket];
  alignas(64) float inv_dir[3][kMaxPacket];
  alignas(64) float abs_slack[kMaxPacket];
  alignas(64) float sorg[3][kMaxPacket];   // origin in sheared axis order (kx, ky, kz)
  alignas(64) float shear[3][kMaxPacket];  // sx, sy, sz of WatertightRay
  alignas(64) float tnear[kMaxPacket];
  alignas(64) float limit[kMaxPacket];  // tfar, then next_up(best_t) once there is a hit
  alignas(64) float best_t[kMaxPacket];
  // The closest hit's edge functions V, W and their sum det (1 for a hit the scalar kernel
  // found, with V = u, W = v): u = V * (1 / det) is computed once per ray at the end, with
  // the single-ray kernel's operations, instead of once per candidate hit.
  alignas(64) float best_V[kMaxPacket];
  alignas(64) float best_W[kMaxPacket];
  alignas(64) float best_det[kMaxPacket];
  alignas(64) float t0[kMaxPacket];
  alignas(64) float t1[kMaxPacket];
  alignas(64) std::uint32_t best_prim[kMaxPacket];
  std::uint64_t parallel[3];  // bit i: dir[axis] == 0 for ray i
  std::uint64_t negative[3];  // bit i: dir[axis] < 0
  std::uint64_t klass[6];     // rays by shear permutation: 2 * kz + (dir[kz] < 0)
  // Occlusion (kd_occluded_packet): the first hit ends its lane (see keep_closest).
  bool any_hit;
};

// What setup_vectors leaves for the caller, as lane bits.
struct SetupMasks {
  std::uint64_t packet = 0;  // set up in p, to traverse
  std::uint64_t slow = 0;    // not handled here: kd_setup_ray's turn
};

// Sets up lanes [0, count) of p (org, inv_dir, abs_slack, t0, t1, tnear, limit, best_t,
// best_det, negative, the shear and the permutation classes) where float is safe; lanes that miss
// the scene box get hits[i] = miss. PacketRays must be zeroed and best_prim filled.
template <int N>
SetupMasks setup_vectors(const KdTreeView& tree, const Ray* rays, int count, PacketRays& p, Hit* hits) {
  SetupMasks out;
  const int nvec = (count + N - 1) / N;
  if (tree.bounds.empty()) {  // kd_setup_ray says Miss for all
    out.slow = count == 64 ? ~0ull : (1ull << count) - 1;
    return out;
  }
  alignas(64) float raw[8][kMaxPacket];  // ox oy oz tnear dx dy dz tfar
  for (int i = 0; i < count; ++i) {
    const Ray& r = rays[i];
    raw[0][i] = r.org.x, raw[1][i] = r.org.y, raw[2][i] = r.org.z, raw[3][i] = r.tnear;
    raw[4][i] = r.dir.x, raw[5][i] = r.dir.y, raw[6][i] = r.dir.z, raw[7][i] = r.tfar;
  }
  for (int i = count; i < nvec * N; ++i)
    for (int k = 0; k < 8; ++k) raw[k][i] = 0.0f;

  const Lanes<N> w;
  const float extent = tree.max_extent_up;
  const vfloat<N> E(extent), E2(extent * extent), zero(0.0f), one(1.0f);
  const vfloat<N> finite_max(3.40282347e38f), rel(static_cast<float>(kKdRelativeSlack));
  const vfloat<N> lo[3] = {vfloat<N>(tree.bounds.lo.x), vfloat<N>(tree.bounds.lo.y), vfloat<N>(tree.bounds.lo.z)};
  const vfloat<N> hi[3] = {vfloat<N>(tree.bounds.hi.x), vfloat<N>(tree.bounds.hi.y), vfloat<N>(tree.bounds.hi.z)};
  for (int v = 0; v < nvec; ++v) {
    const int o = v * N;
    vfloat<N> org[3], dir[3];
    for (int a = 0; a < 3; ++a) {
      org[a] = load(w, raw[a] + o);
      dir[a] = load(w, raw[4 + a] + o);
    }
    const vfloat<N> tnear = load(w, raw[3] + o), tfar = load(w, raw[7] + o);
    // tfar may be +inf (unbounded); tnear must be finite (inf - inf would be NaN below).
    const vbool<N> in_packet = first_lanes(w, count - o);
    vbool<N> ok = in_packet & (abs(tnear) <= finite_max) & (tfar >= -finite_max);
    vfloat<N> max_dir = zero, reach_max = zero, reach[3], inv[3];
    for (int a = 0; a < 3; ++a) {
      const vfloat<N> ad = abs(dir[a]);
      ok = ok & (abs(org[a]) <= finite_max) & (ad <= finite_max) & (ad >= vfloat<N>(0x1p-60f));
      max_dir = max(max_dir, ad);
      reach[a] = max(abs(org[a] - lo[a]), abs(org[a] - hi[a]));
      reach_max = max(reach_max, reach[a]);
      inv[a] = one / dir[a];
    }
    // E^2 max(E, D) / max|dir| within [2^-50, 2^90], compared without the division.
    const vfloat<N> scale = E2 * max(E, reach_max);
    const vfloat<N> abs_slack = vfloat<N>(static_cast<float>(kKdExtentSlack)) * E / max_dir;
    ok = ok & (scale >= vfloat<N>(0x1p-50f) * max_dir) & (scale <= vfloat<N>(0x1p90f) * max_dir) &
         (abs_slack >= vfloat<N>(0x1p-90f)) & (abs_slack <= vfloat<N>(0x1p60f));
    vfloat<N> t0 = tnear - (abs(tnear) * rel + abs_slack);
    vfloat<N> t1 = tfar + (abs(tfar) * rel + abs_slack);
    for (int a = 0; a < 3; ++a) {
      ok = ok & (reach[a] * abs(inv[a]) <= vfloat<N>(0x1p60f));
      const vfloat<N> ta = (lo[a] - org[a]) * inv[a], tb = (hi[a] - org[a]) * inv[a];
      const vfloat<N> enter = min(ta, tb), leave = max(ta, tb);
      t0 = max(t0, enter - (abs(enter) * rel + abs_slack));
      t1 = min(t1, leave + (abs(leave) * rel + abs_slack));
    }
    const vfloat<N> t_limit(0x1p64f);
    ok = ok & (abs(t0) <= t_limit);
    ok = ok & (abs(t1) <= t_limit);
    const std::uint32_t ok_bits = static_cast<std::uint32_t>(movemask(ok));
    const std::uint32_t valid_bits = static_cast<std::uint32_t>(movemask(in_packet));
    const std::uint32_t in_bits = static_cast<std::uint32_t>(movemask(ok & (t0 <= t1)));
    out.slow |= std::uint64_t(valid_bits & ~ok_bits) << o;
    out.packet |= std::uint64_t(in_bits) << o;
    for (std::uint32_t m = ok_bits & ~in_bits; m != 0; m &= m - 1) hits[o + __builtin_ctz(m)] = kd::miss();

    for (int a = 0; a < 3; ++a) {
      store(p.org[a] + o, org[a]);
      store(p.inv_dir[a] + o, inv[a]);
      p.negative[a] |= std::uint64_t(static_cast<std::uint32_t>(movemask(dir[a] < zero)) & in_bits) << o;
    }
    store(p.abs_slack + o, abs_slack);
    store(p.t0 + o, t0);
    store(p.t1 + o, t1);
    store(p.tnear + o, tnear);
    store(p.limit + o, tfar);
    store(p.best_t + o, tfar);
    store(p.best_det + o, one);

    // WatertightRay's permutation (kz the dominant axis, kx and ky swapped when dir[kz] < 0)
    // and shear, with the same float divisions, so the leaf test sees the same constants.
    const vfloat<N> ax = abs(dir[0]), ay = abs(dir[1]), az = abs(dir[2]);
    const vbool<N> kz0 = (ax > ay) & (ax > az);
    const vbool<N> kz1 = andnot(ay > az, ax > ay);
    const vbool<N> kz2 = !(kz0 | kz1);
    const vfloat<N> dz = select(kz0, dir[0], select(kz1, dir[1], dir[2]));
    const vfloat<N> dx0 = select(kz0, dir[1], select(kz1, dir[2], dir[0]));
    const vfloat<N> dy0 = select(kz0, dir[2], select(kz1, dir[0], dir[1]));
    const vfloat<N> oz = select(kz0, org[0], select(kz1, org[1], org[2]));
    const vfloat<N> ox0 = select(kz0, org[1], select(kz1, org[2], org[0]));
    const vfloat<N> oy0 = select(kz0, org[2], select(kz1, org[0], org[1]));
    const vbool<N> swapped = dz < zero;
    store(p.sorg[0] + o, select(swapped, oy0, ox0));
    store(p.sorg[1] + o, select(swapped, ox0, oy0));
    store(p.sorg[2] + o, oz);
    store(p.shear[0] + o, select(swapped, dy0, dx0) / dz);
    store(p.shear[1] + o, select(swapped, dx0, dy0) / dz);
    store(p.shear[2] + o, select(kz0, inv[0], select(kz1, inv[1], inv[2])));  // 1 / dz, already divided
    const vbool<N> kz[3] = {kz0, kz1, kz2};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t straight = static_cast<std::uint32_t>(movemask(andnot(kz[k], swapped))) & in_bits;
      const std::uint32_t flipped = static_cast<std::uint32_t>(movemask(kz[k] & swapped)) & in_bits;
      p.klass[2 * k] |= std::uint64_t(straight) << o;
      p.klass[2 * k + 1] |= std::uint64_t(flipped) << o;
    }
  }
  return out;
}

}  // namespace kdp
}  // namespace lancer::LANCER_ISA
