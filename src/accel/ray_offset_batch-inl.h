// The batch origin solver of ray_offset_batch.h, for one ISA: SurfaceOffset's plane, start
// and attempts (ray_offset.h) for LANCER_BATCH_LANES rays per vector, in GCC's vector
// extensions, which the TU's flags turn into that ISA's instructions.
//
// Every lane performs exactly the scalar solver's float and double operations, in its
// order (the build passes -ffp-contract=off: no fused multiply-adds), so the origins are
// its origins bit for bit: std::max(a, b) is a < b ? b : a, std::fabs clears the sign bit,
// glm::abs is x >= 0 ? x : -x, glm::dot sums x, y, then z. A lane leaves the vector path,
// to be solved by SurfaceOffset itself, wherever the scalar solver would leave its common
// path: a triangle without area (or a point that is not finite), a direction it cannot use,
// a near tie between two axes (several shear permutations), a bound near tangent or not
// finite, or more than kBatchAttempts tries. std::sqrt is correctly rounded, as each
// lane's __builtin_sqrt is.
//
// ODR: everything here lives in lancer::LANCER_ISA and calls no inline function of
// namespace lancer, glm or std (only builtins), so no copy built with this ISA's flags can
// stand in for a generic one.
#pragma once

#include "simd/isa_namespace.h"

#include <cstdint>

#include "accel/ray_offset_batch.h"
#include "simd/batch_lanes-inl.h"

namespace lancer::LANCER_ISA {
namespace offset_lanes {

using namespace batch_lanes;

using ray_offset_batch::kMaxLanes;
using ray_offset_detail::kMinHeight;

inline vd broadcast(double x) { return vd{} + x; }
inline vf broadcast(float x) { return vf{} + x; }

inline vl wide(vi m) { return __builtin_convertvector(m, vl); }

// std::fabs: the sign bit cleared.
inline vd fabs(vd v) { return (vd)((vl)v & 0x7FFFFFFFFFFFFFFFll); }
inline vf fabs(vf v) { return (vf)((vi)v & 0x7FFFFFFF); }
// glm::abs: x >= 0 ? x : -x.
inline vd glm_abs(vd v) { return v >= 0.0 ? v : -v; }
// std::max(a, b): a < b ? b : a.
inline vd max(vd a, vd b) { return a < b ? b : a; }
inline vf max(vf a, vf b) { return a < b ? b : a; }


// Component k (per lane, 0 to 2) of (x, y, z).
inline vf pick(vi k, vf x, vf y, vf z) { return k == 0 ? x : (k == 1 ? y : z); }
inline vd pick(vl k, vd x, vd y, vd z) { return k == 0 ? x : (k == 1 ? y : z); }

inline bool none(vl m) {
  for (int i = 0; i < N; ++i)
    if (m[i]) return false;
  return true;
}

// One vector of lanes, offset `o` in the Lanes arrays, of which the first `valid` are in use.
inline std::uint64_t solve_vector(const ray_offset_batch::Lanes& L, int o, int valid, float out[3][kMaxLanes]) {
  using namespace ray_offset_batch;
  const vf v[3][3] = {{load(L.tri[0] + o), load(L.tri[1] + o), load(L.tri[2] + o)},
                      {load(L.tri[3] + o), load(L.tri[4] + o), load(L.tri[5] + o)},
                      {load(L.tri[6] + o), load(L.tri[7] + o), load(L.tri[8] + o)}};
  const vf p[3] = {load(L.p[0] + o), load(L.p[1] + o), load(L.p[2] + o)};
  const vf n_given[3] = {load(L.n[0] + o), load(L.n[1] + o), load(L.n[2] + o)};
  const vf target[3] = {load(L.target[0] + o), load(L.target[1] + o), load(L.target[2] + o)};
  const vi towards = load(L.towards + o) != 0;
  const vd p_d[3] = {to_double(p[0]), to_double(p[1]), to_double(p[2])};

  // SurfaceOffset::make_plane: the plane in double.
  const vd corner[3] = {to_double(v[0][0]), to_double(v[0][1]), to_double(v[0][2])};
  vd e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = to_double(v[1][k]) - corner[k];
    e2[k] = to_double(v[2][k]) - corner[k];
  }
  const vd cross[3] = {e1[1] * e2[2] - e2[1] * e1[2], e1[2] * e2[0] - e2[2] * e1[0], e1[0] * e2[1] - e2[0] * e1[1]};
  const vd len = sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
  const vl valid_plane = (len > 0.0) & finite(len) & wide(finite(p[0] + p[1] + p[2]));
  const vd inv_len = 1.0 / len;
  const vd plane_normal[3] = {cross[0] * inv_len, cross[1] * inv_len, cross[2] * inv_len};
  const vd products[3] = {fabs(e1[1] * e2[2]) + fabs(e1[2] * e2[1]), fabs(e1[2] * e2[0]) + fabs(e1[0] * e2[2]),
                          fabs(e1[0] * e2[1]) + fabs(e1[1] * e2[0])};
  const vd error_scale = 0x1p-51 * inv_len;
  vd weights[3];
  for (int k = 0; k < 3; ++k) {
    const vd normal_error = error_scale * products[k] + 0x1p-50 * glm_abs(plane_normal[k]);
    weights[k] = normal_error + 0x1p-50 * glm_abs(plane_normal[k]);
  }
  vd p_rel[3];
  for (int k = 0; k < 3; ++k) p_rel[k] = p_d[k] - corner[k];
  const vd p_height = p_rel[0] * plane_normal[0] + p_rel[1] * plane_normal[1] + p_rel[2] * plane_normal[2];
  const vd p_height_error =
      glm_abs(p_rel[0]) * weights[0] + glm_abs(p_rel[1]) * weights[1] + glm_abs(p_rel[2]) * weights[2];
  vd o_rounding = broadcast(0.0);
  for (int k = 0; k < 3; ++k) o_rounding += (2.0 * kGamma1) * fabs(plane_normal[k] * p_d[k]);

  // SurfaceOffset::start: the side, the deficit and the first height, for the ray from p.
  vf dir0[3];
  for (int k = 0; k < 3; ++k) dir0[k] = towards ? target[k] - p[k] : target[k];
  const vf a0[3] = {fabs(dir0[0]), fabs(dir0[1]), fabs(dir0[2])};
  const vf m0 = max(a0[0], max(a0[1], a0[2]));
  const vi usable0 = (m0 > 0.0f) & finite(m0) & finite(dir0[0] + dir0[1] + dir0[2]);
  const vd toward = to_double(dir0[0]) * plane_normal[0] + to_double(dir0[1]) * plane_normal[1] +
                    to_double(dir0[2]) * plane_normal[2];
  const vd given_side = to_double(n_given[0]) * plane_normal[0] + to_double(n_given[1]) * plane_normal[1] +
                        to_double(n_given[2]) * plane_normal[2];
  const vl flip = (toward < 0.0) | ((toward == 0.0) & (given_side < 0.0));
  const vd normal[3] = {flip ? -plane_normal[0] : plane_normal[0], flip ? -plane_normal[1] : plane_normal[1],
                        flip ? -plane_normal[2] : plane_normal[2]};
  const vd deficit = max(broadcast(0.0), (flip ? p_height : -p_height) + p_height_error);
  const vd two_deficit = 2.0 * deficit;

  vd h = kMinHeight + two_deficit + o_rounding;
  vl lane{};
  for (int i = 0; i < N; ++i) lane[i] = i;
  vl done = lane >= valid;  // lanes not in use count as done
  // Lanes given up: the scalar solver's, from the start where the bound does not apply.
  vl left = ~done & ~(valid_plane & wide(usable0));
  vf org[3] = {p[0], p[1], p[2]};
  for (int attempt = 0; attempt < kBatchAttempts; ++attempt) {
    const vl active = ~(done | left);
    if (none(active)) break;
    // o = vec3(dvec3(p) + h * normal)
    vf ox[3];
    for (int k = 0; k < 3; ++k) ox[k] = to_float(p_d[k] + h * normal[k]);
    // d = dir_for(o)
    vf d[3];
    for (int k = 0; k < 3; ++k) d[k] = towards ? target[k] - ox[k] : target[k];
    // usable(d)
    const vf a[3] = {fabs(d[0]), fabs(d[1]), fabs(d[2])};
    const vf m = max(a[0], max(a[1], a[2]));
    const vi usable = (m > 0.0f) & finite(m) & finite(d[0] + d[1] + d[2]);
    // The permutations the kernel could pick: exactly one, or the lane leaves.
    const vf tie = m * (1.0f - 0x1p-16f);
    const vi c0 = a[0] >= tie, c1 = a[1] >= tie, c2 = a[2] >= tie;
    const vi one_axis = ((c0 & 1) + (c1 & 1) + (c2 & 1)) == 1;
    const vi kz = c0 ? vi{} + 0 : (c1 ? vi{} + 1 : vi{} + 2);
    const vi kx = kz == 2 ? vi{} + 0 : kz + 1;
    const vi ky = kx == 2 ? vi{} + 0 : kx + 1;
    const vl kx_l = wide(kx), ky_l = wide(ky), kz_l = wide(kz);
    // make_shear
    const vf dz = pick(kz, d[0], d[1], d[2]);
    const vf sx = pick(kx, d[0], d[1], d[2]) / dz, sy = pick(ky, d[0], d[1], d[2]) / dz, sz = 1.0f / dz;
    const vd n_kx = pick(kx_l, normal[0], normal[1], normal[2]), n_ky = pick(ky_l, normal[0], normal[1], normal[2]),
             n_kz = pick(kz_l, normal[0], normal[1], normal[2]);
    const vd sx_d = to_double(sx), sy_d = to_double(sy);
    const vd nd = (n_kx * sx_d + n_ky * sy_d + n_kz) / to_double(sz);
    // have = dot(rel, normal) - height_error(rel)
    vd rel[3];
    for (int k = 0; k < 3; ++k) rel[k] = to_double(ox[k]) - corner[k];
    const vd dot = rel[0] * normal[0] + rel[1] * normal[1] + rel[2] * normal[2];
    const vd error = glm_abs(rel[0]) * weights[0] + glm_abs(rel[1]) * weights[1] + glm_abs(rel[2]) * weights[2];
    const vd have = dot - error;
    // required_height(tri, o, normal, shear)
    const vf o_kx = pick(kx, ox[0], ox[1], ox[2]), o_ky = pick(ky, ox[0], ox[1], ox[2]),
             o_kz = pick(kz, ox[0], ox[1], ox[2]);
    vd X[3], Y[3];
    vd z_max = broadcast(0.0), s = broadcast(0.0);
    for (int i = 0; i < 3; ++i) {
      const vf ax = pick(kx, v[i][0], v[i][1], v[i][2]) - o_kx, ay = pick(ky, v[i][0], v[i][1], v[i][2]) - o_ky,
               az = pick(kz, v[i][0], v[i][1], v[i][2]) - o_kz;
      const vf x = ax - sx * az, y = ay - sy * az, z = sz * az;
      X[i] = to_double(x);
      Y[i] = to_double(y);
      z_max = max(z_max, to_double(fabs(z)));
      const vd az_d = to_double(az);
      const vd shift = fabs(n_kz * az_d) + fabs(n_kx) * (to_double(fabs(ax) + fabs(x)) + fabs(sx_d * az_d)) +
                       fabs(n_ky) * (to_double(fabs(ay) + fabs(y)) + fabs(sy_d * az_d));
      s = max(s, shift);
    }
    s = kGamma2 * s + 3.0 * kSubnormalError;
    vd e[3], err[3];
    for (int i = 0; i < 3; ++i) {
      const int j = i == 2 ? 0 : i + 1, k = j == 2 ? 0 : j + 1;
      const vd p1 = X[k] * Y[j], p2 = Y[k] * X[j];
      e[i] = p1 - p2;
      err[i] = kGamma2 * (fabs(p1) + fabs(p2)) + 3.0 * kSubnormalError;
    }
    const vl some_positive = (e[0] > err[0]) | (e[1] > err[1]) | (e[2] > err[2]);
    const vl some_negative = (e[0] < -err[0]) | (e[1] < -err[1]) | (e[2] < -err[2]);
    const vl misses = some_positive & some_negative;
    const vd E = err[0] + err[1] + err[2];
    const vd sum = fabs(e[0] + e[1] + e[2]);
    const vd D = sum * (1.0 - 0x1p-50) - E;
    // Near tangent (the scalar solver's other branch): the lane leaves.
    const vl regular = (nd > 0.0) & (D > 2.0 * E) & finite(nd);
    const vd B = misses ? broadcast(1.0) : (fabs(e[0]) + fabs(e[1]) + fabs(e[2])) * (1.0 + 0x1p-50) / sum;
    z_max *= 1.0 + kGamma1;
    const vd bound =
        (s * B * (D + E) + nd * ((E + kGamma3 * D) * z_max + 8.0 * kSubnormalError)) / (D - E) * (1.0 + 0x1p-20);
    const vd need = max(broadcast(0.0), bound);
    const vl ok = wide(usable & one_axis) & regular & finite(need);
    left |= active & ~ok;
    const vl success = active & ok & (have > 0.0) & (have >= need);
    const vi success_f = __builtin_convertvector(success, vi);
    for (int k = 0; k < 3; ++k) org[k] = success_f ? ox[k] : org[k];
    done |= success;
    // h = max(2 h, 1.25 need + 2 deficit + o_rounding) for the lanes still going.
    h = (active & ok & ~success) ? max(2.0 * h, 1.25 * need + two_deficit + o_rounding) : h;
  }
  for (int k = 0; k < 3; ++k) store(out[k] + o, org[k]);
  std::uint64_t bits = 0;
  for (int i = 0; i < valid; ++i)
    if (done[i]) bits |= std::uint64_t{1} << i;
  return bits;
}

}  // namespace offset_lanes

// ray_offset_batch::SolveLanesFn for this ISA.
inline std::uint64_t solve_origin_lanes_impl(const ray_offset_batch::Lanes& lanes, int count,
                                             float out[3][ray_offset_batch::kMaxLanes]) {
  return batch_lanes::solve_lanes(count,
                                  [&](int o, int valid) { return offset_lanes::solve_vector(lanes, o, valid, out); });
}

}  // namespace lancer::LANCER_ISA
