// The batch surface solver of surface_batch.h, for one ISA: make_surface_point's geometry
// (surface.cpp) for LANCER_BATCH_LANES hits per vector, in GCC's vector extensions, which
// the TU's flags turn into that ISA's instructions.
//
// Every lane performs exactly make_surface_point's float and double operations, in its
// order (glm sums a dot product as (x + y) + z; scalar * vec3 and vec3 / scalar act per
// component; -ffp-contract=off: no fused multiply-adds), so the geometry is its geometry
// bit for bit. A lane whose normal has no usable length leaves (make_surface_point then
// falls back on the ray's direction). std::sqrt is correctly rounded, as each lane's
// __builtin_sqrt is.
//
// ODR: everything here lives in lancer::LANCER_ISA and calls no inline function of
// namespace lancer, glm or std (only builtins).
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "render/surface_batch.h"
#include "simd/batch_lanes-inl.h"

namespace lancer::LANCER_ISA {
namespace surface_lanes {

using namespace batch_lanes;

using surface_batch::kMaxLanes;

// One vector of lanes at offset `o`, the first `valid` in use.
inline std::uint64_t solve_vector(const surface_batch::Lanes& L, int o, int valid, surface_batch::Out& out) {
  vf a[3], b[3], c[3], n0[3], n1[3], n2[3], d[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = load(L.corner[k] + o);
    b[k] = load(L.corner[3 + k] + o);
    c[k] = load(L.corner[6 + k] + o);
    n0[k] = load(L.normal[k] + o);
    n1[k] = load(L.normal[3 + k] + o);
    n2[k] = load(L.normal[6 + k] + o);
    d[k] = load(L.dir[k] + o);
  }
  const vf u = load(L.u + o), v = load(L.v + o);
  const vi has_normals = load(L.has_normals + o) != 0;

  // p = vec3(dw * dvec3(a) + du * dvec3(b) + dv * dvec3(c)), dw = 1 - du - dv.
  const vd du = to_double(u), dv = to_double(v);
  const vd dw = (1.0 - du) - dv;
  vf p[3];
  for (int k = 0; k < 3; ++k) p[k] = to_float((dw * to_double(a[k]) + du * to_double(b[k])) + dv * to_double(c[k]));

  // ng = cross(b - a, c - a) / its length.
  const vf e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const vf e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const vf cross[3] = {e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0], e1[0] * e2[1] - e2[0] * e1[1]};
  const vf len = sqrt((cross[0] * cross[0] + cross[1] * cross[1]) + cross[2] * cross[2]);
  const vi usable = (len > 0.0f) & finite(len);
  vf ng[3] = {cross[0] / len, cross[1] / len, cross[2] / len};

  // ns: the stored normals interpolated with w = 1 - u - v, normalised where usable.
  const vf w = (1.0f - u) - v;
  const vf interp[3] = {(w * n0[0] + u * n1[0]) + v * n2[0], (w * n0[1] + u * n1[1]) + v * n2[1],
                        (w * n0[2] + u * n1[2]) + v * n2[2]};
  const vf ilen = sqrt((interp[0] * interp[0] + interp[1] * interp[1]) + interp[2] * interp[2]);
  const vi use_interp = has_normals & (ilen > 1e-12f) & finite(ilen);
  vf ns[3];
  for (int k = 0; k < 3; ++k) ns[k] = use_interp ? interp[k] / ilen : ng[k];

  // Flipped to face the ray.
  const vi front = ((ng[0] * d[0] + ng[1] * d[1]) + ng[2] * d[2]) <= 0.0f;
  for (int k = 0; k < 3; ++k) {
    ng[k] = front ? ng[k] : -ng[k];
    ns[k] = front ? ns[k] : -ns[k];
    store(out.p[k] + o, p[k]);
    store(out.ng[k] + o, ng[k]);
    store(out.ns[k] + o, ns[k]);
  }
  store(out.front + o, front);
  std::uint64_t bits = 0;
  for (int i = 0; i < valid; ++i)
    if (usable[i]) bits |= std::uint64_t{1} << i;
  return bits;
}

}  // namespace surface_lanes

// surface_batch::SolveLanesFn for this ISA.
inline std::uint64_t solve_surface_lanes_impl(const surface_batch::Lanes& lanes, int count, surface_batch::Out& out) {
  return batch_lanes::solve_lanes(count,
                                  [&](int o, int valid) { return surface_lanes::solve_vector(lanes, o, valid, out); });
}

}  // namespace lancer::LANCER_ISA
