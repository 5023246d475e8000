// The one float ray setup of kd-tree traversal, written once over the width N: packets
// instantiate it at their vector width (kd_packet_setup-inl.h), single rays at width 1
// (kd_traverse-inl.h), both inside each ISA's namespace. Compiled once per ISA in
// namespace lancer::LANCER_ISA, like the traversal itself; include the ISA's vector header
// first (width 1 comes from simd/vfloat1-inl.h).
//
// Which rays: float is plainly safe for a finite origin, direction and tnear, every
// direction component at least 2^-60, and the magnitudes the double setup
// (kd_setup_ray_double, kd_traverse.cpp) checks well inside its limits (E^2 max(E, D) /
// max|dir| within [2^-50, 2^90], abs_slack within [2^-90, 2^60], plane distances and the
// clipped interval below 2^60 and 2^64). Lanes outside (axis-parallel, huge, tiny, NaN,
// infinite) are declined (ok false) and take the double setup, so the rare cases keep one
// careful implementation.
//
// The float values differ from the double setup's rounded doubles by a few 2^-24 relative
// (1/dir, the box distances and the slack each round once more), which the 2^-20 term of
// kKdRelativeSlack is there to absorb (kd_traverse_setup.h); the interval stays a superset
// of the cells that can hold the oracle's answer, so the hits stay exact. A lane whose
// clipped interval is empty misses the widened scene box: nothing can hit it. Every limit
// is checked once at the end: a lane outside them may compute garbage on the way (never a
// trap: float exceptions are masked).
#pragma once

#include "simd/isa_namespace.h"
#include "simd/vfloat1-inl.h"

#include "accel/kd_traverse.h"
#include "accel/kd_traverse_setup.h"

namespace lancer::LANCER_ISA {
namespace kdr {

// The traversal's constants of N rays: 1 / dir, the absolute slack, and [tnear, tfar]
// clipped to the scene box, both ends widened by the slack (kd_traverse_setup.h).
template <int N>
struct ClipLanes {
  vbool<N> ok;      // set up in float (else the double setup's turn)
  vbool<N> inside;  // ok, and the interval is not empty
  vfloat<N> inv[3];
  vfloat<N> abs_slack, t0, t1;
};

template <int N>
ClipLanes<N> clip_lanes(const KdTreeView& tree, const vfloat<N> org[3], const vfloat<N> dir[3], vfloat<N> tnear,
                        vfloat<N> tfar, vbool<N> live) {
  using namespace width1;  // the float overloads, when N is 1
  const float extent = tree.max_extent_up;
  const vfloat<N> E(extent), E2(extent * extent), zero(0.0f), one(1.0f);
  const vfloat<N> finite_max(3.40282347e38f), rel(static_cast<float>(kKdRelativeSlack));
  const vfloat<N> lo[3] = {vfloat<N>(tree.bounds.lo.x), vfloat<N>(tree.bounds.lo.y), vfloat<N>(tree.bounds.lo.z)};
  const vfloat<N> hi[3] = {vfloat<N>(tree.bounds.hi.x), vfloat<N>(tree.bounds.hi.y), vfloat<N>(tree.bounds.hi.z)};
  ClipLanes<N> c;
  // tfar may be +inf (unbounded); tnear must be finite (inf - inf would be NaN below).
  vbool<N> ok = live & (abs(tnear) <= finite_max) & (tfar >= -finite_max);
  vfloat<N> max_dir = zero, reach_max = zero, reach[3];
  for (int a = 0; a < 3; ++a) {
    const vfloat<N> ad = abs(dir[a]);
    ok = ok & (abs(org[a]) <= finite_max) & (ad <= finite_max) & (ad >= vfloat<N>(0x1p-60f));
    max_dir = max(max_dir, ad);
    reach[a] = max(abs(org[a] - lo[a]), abs(org[a] - hi[a]));
    reach_max = max(reach_max, reach[a]);
    c.inv[a] = one / dir[a];
  }
  // E^2 max(E, D) / max|dir| within [2^-50, 2^90], compared without the division.
  const vfloat<N> scale = E2 * max(E, reach_max);
  c.abs_slack = vfloat<N>(static_cast<float>(kKdExtentSlack)) * E / max_dir;
  ok = ok & (scale >= vfloat<N>(0x1p-50f) * max_dir) & (scale <= vfloat<N>(0x1p90f) * max_dir) &
       (c.abs_slack >= vfloat<N>(0x1p-90f)) & (c.abs_slack <= vfloat<N>(0x1p60f));
  c.t0 = tnear - (abs(tnear) * rel + c.abs_slack);
  c.t1 = tfar + (abs(tfar) * rel + c.abs_slack);
  for (int a = 0; a < 3; ++a) {
    ok = ok & (reach[a] * abs(c.inv[a]) <= vfloat<N>(0x1p60f));
    const vfloat<N> ta = (lo[a] - org[a]) * c.inv[a], tb = (hi[a] - org[a]) * c.inv[a];
    const vfloat<N> enter = min(ta, tb), leave = max(ta, tb);
    c.t0 = max(c.t0, enter - (abs(enter) * rel + c.abs_slack));
    c.t1 = min(c.t1, leave + (abs(leave) * rel + c.abs_slack));
  }
  const vfloat<N> t_limit(0x1p64f);
  ok = ok & (abs(c.t0) <= t_limit);
  ok = ok & (abs(c.t1) <= t_limit);
  c.ok = ok;
  c.inside = ok & (c.t0 <= c.t1);
  return c;
}

// WatertightRay's permutation (kz the dominant axis; kx, ky the next two in cyclic order,
// swapped when dir[kz] < 0 to keep the winding) and shear, with the same float divisions,
// so that every kernel's leaf test sees the oracle's constants. Any finite or infinite
// direction; the double setup's rays use it too.
template <int N>
struct ShearLanes {
  vfloat<N> sorg[3];   // origin in sheared axis order (kx, ky, kz)
  vfloat<N> shear[3];  // sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1 / d[kz]
  vbool<N> kz[3];      // which axis is kz
  vbool<N> swapped;    // dir[kz] < 0
};

template <int N>
ShearLanes<N> shear_lanes(const vfloat<N> org[3], const vfloat<N> dir[3]) {
  using namespace width1;
  const vfloat<N> zero(0.0f), one(1.0f);
  const vfloat<N> ax = abs(dir[0]), ay = abs(dir[1]), az = abs(dir[2]);
  ShearLanes<N> s;
  s.kz[0] = (ax > ay) & (ax > az);
  s.kz[1] = andnot(ay > az, ax > ay);
  s.kz[2] = !(s.kz[0] | s.kz[1]);
  const vfloat<N> dz = select(s.kz[0], dir[0], select(s.kz[1], dir[1], dir[2]));
  const vfloat<N> dx0 = select(s.kz[0], dir[1], select(s.kz[1], dir[2], dir[0]));
  const vfloat<N> dy0 = select(s.kz[0], dir[2], select(s.kz[1], dir[0], dir[1]));
  const vfloat<N> oz = select(s.kz[0], org[0], select(s.kz[1], org[1], org[2]));
  const vfloat<N> ox0 = select(s.kz[0], org[1], select(s.kz[1], org[2], org[0]));
  const vfloat<N> oy0 = select(s.kz[0], org[2], select(s.kz[1], org[0], org[1]));
  s.swapped = dz < zero;
  s.sorg[0] = select(s.swapped, oy0, ox0);
  s.sorg[1] = select(s.swapped, ox0, oy0);
  s.sorg[2] = oz;
  s.shear[0] = select(s.swapped, dy0, dx0) / dz;
  s.shear[1] = select(s.swapped, dx0, dy0) / dz;
  s.shear[2] = one / dz;
  return s;
}

}  // namespace kdr
}  // namespace lancer::LANCER_ISA
