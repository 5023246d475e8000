// Per-ray setup of a packet, N lanes at a time, in float (kd_packet-inl.h's first step):
// the one width-generic setup (kd_ray_setup-inl.h) at the vector width, laid out in the
// packet's SoA arrays. Compiled once per ISA inside namespace lancer::LANCER_ISA, like
// the traversal itself. Lanes it declines take kd_setup_ray_double, one at a time.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "accel/kd_ray_setup-inl.h"
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
  std::uint64_t slow = 0;    // not handled here: kd_setup_ray_double's turn
};

// Sets up lanes [0, count) of p (org, inv_dir, abs_slack, t0, t1, tnear, limit, best_t,
// best_det, negative, the shear and the permutation classes) where float is safe; lanes that miss
// the scene box get hits[i] = miss. PacketRays must be zeroed and best_prim filled.
template <int N>
SetupMasks setup_vectors(const KdTreeView& tree, const Ray* rays, int count, PacketRays& p, Hit* hits) {
  SetupMasks out;
  const int nvec = (count + N - 1) / N;
  if (tree.bounds.empty()) {  // kd_setup_ray_double says Miss for all
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
  const vfloat<N> zero(0.0f), one(1.0f);
  for (int v = 0; v < nvec; ++v) {
    const int o = v * N;
    vfloat<N> org[3], dir[3];
    for (int a = 0; a < 3; ++a) {
      org[a] = load(w, raw[a] + o);
      dir[a] = load(w, raw[4 + a] + o);
    }
    const vfloat<N> tnear = load(w, raw[3] + o), tfar = load(w, raw[7] + o);
    const vbool<N> in_packet = first_lanes(w, count - o);
    const kdr::ClipLanes<N> c = kdr::clip_lanes<N>(tree, org, dir, tnear, tfar, in_packet);
    const std::uint32_t ok_bits = static_cast<std::uint32_t>(movemask(c.ok));
    const std::uint32_t valid_bits = static_cast<std::uint32_t>(movemask(in_packet));
    const std::uint32_t in_bits = static_cast<std::uint32_t>(movemask(c.inside));
    out.slow |= std::uint64_t(valid_bits & ~ok_bits) << o;
    out.packet |= std::uint64_t(in_bits) << o;
    for (std::uint32_t m = ok_bits & ~in_bits; m != 0; m &= m - 1) hits[o + __builtin_ctz(m)] = kd::miss();

    for (int a = 0; a < 3; ++a) {
      store(p.org[a] + o, org[a]);
      store(p.inv_dir[a] + o, c.inv[a]);
      p.negative[a] |= std::uint64_t(static_cast<std::uint32_t>(movemask(dir[a] < zero)) & in_bits) << o;
    }
    store(p.abs_slack + o, c.abs_slack);
    store(p.t0 + o, c.t0);
    store(p.t1 + o, c.t1);
    store(p.tnear + o, tnear);
    store(p.limit + o, tfar);
    store(p.best_t + o, tfar);
    store(p.best_det + o, one);
    const kdr::ShearLanes<N> sh = kdr::shear_lanes<N>(org, dir);
    for (int k = 0; k < 3; ++k) {
      store(p.sorg[k] + o, sh.sorg[k]);
      store(p.shear[k] + o, sh.shear[k]);
      const std::uint32_t straight = static_cast<std::uint32_t>(movemask(andnot(sh.kz[k], sh.swapped))) & in_bits;
      const std::uint32_t flipped = static_cast<std::uint32_t>(movemask(sh.kz[k] & sh.swapped)) & in_bits;
      p.klass[2 * k] |= std::uint64_t(straight) << o;
      p.klass[2 * k + 1] |= std::uint64_t(flipped) << o;
    }
  }
  return out;
}

}  // namespace kdp
}  // namespace lancer::LANCER_ISA
