// The generic parts of single-ray kd-tree traversal: per-ray setup, the scan fallback, the
// exact scalar test of one slot, and the dispatch table. The traversal loops themselves
// are templates in kd_traverse-inl.h, compiled once per ISA.
#include "accel/kd_traverse.h"

#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "accel/kd_traverse_isa.h"
#include "accel/kd_traverse_setup.h"
#include "accel/kd_tree.h"
#include "accel/watertight.h"

namespace lancer {
namespace {

double slack(double t, double abs_slack) { return std::fabs(t) * kKdRelativeSlack + abs_slack; }

// Plain comparisons: std::fmax is a libm call here, once per axis and ray. Inputs are not NaN.
double max_of(double a, double b) { return a > b ? a : b; }
double min_of(double a, double b) { return a < b ? a : b; }

// float(d) rounded towards -inf (down = true) or +inf.
float round_float(double d, bool down) {
  float f = static_cast<float>(d);
  if (down && double(f) > d) f = std::nextafter(f, -kInfinity);
  if (!down && double(f) < d) f = std::nextafter(f, kInfinity);
  return f;
}

void load_triangle(const KdTreeView& tree, std::uint32_t slot, glm::vec3 v[3]) {
  const std::uint32_t w = tree.block_width;
  const float* b = tree.blocks + std::size_t(slot / w) * 9 * w + slot % w;
  for (std::uint32_t k = 0; k < 3; ++k) v[k] = glm::vec3(b[k * w], b[(3 + k) * w], b[(6 + k) * w]);
}

}  // namespace

float kd_max_extent_up(const Bounds3& b) {
  double e = 0.0;
  for (int a = 0; a < 3; ++a) e = max_of(e, double(b.hi[a]) - double(b.lo[a]));
  float f = static_cast<float>(e);
  if (double(f) < e) f = std::nextafter(f, kInfinity);
  return f;
}

KdTreeView view(const KdTree& tree) {
  return {tree.nodes().data(),
          tree.blocks().data(),
          tree.leaf_prims().data(),
          static_cast<std::uint32_t>(tree.leaf_prims().size()),
          static_cast<std::uint32_t>(tree.block_width()),
          tree.bounds(),
          tree.max_extent_up()};
}

// Sets up the ray and clips [tnear, tfar] to the scene box (both widened by the slack),
// or says why the ray does not traverse (see the exactness comment in kd_traverse-inl.h).
KdRaySetup kd_setup_ray(const KdTreeView& tree, const Ray& ray) {
  KdRaySetup s{};
  if (kd_setup_ray_float(tree, ray, s)) return s;  // the common case, without double divisions
  return kd_setup_ray_double(tree, ray);
}

KdRaySetup kd_setup_ray_double(const KdTreeView& tree, const Ray& ray) {
  KdRaySetup s{};
  s.plan = KdPlan::Miss;
  if (tree.bounds.empty() || std::isnan(ray.tnear) || std::isnan(ray.tfar)) return s;  // nothing to hit
  double max_dir = 0.0, max_extent = 0.0, distance = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(ray.org[a]) || !std::isfinite(ray.dir[a])) {
      s.plan = KdPlan::Scan;
      return s;
    }
    const double lo = tree.bounds.lo[a], hi = tree.bounds.hi[a];
    max_dir = max_of(max_dir, std::fabs(double(ray.dir[a])));
    max_extent = max_of(max_extent, hi - lo);
    distance = max_of(distance, max_of(std::fabs(ray.org[a] - lo), std::fabs(ray.org[a] - hi)));
  }
  if (max_dir == 0.0) return s;
  const double magnitude = max_extent * max_extent * max_of(max_extent, distance) / max_dir;
  if (magnitude < 0x1p-60 || magnitude > 0x1p100 || max_extent > 0x1p50) {
    s.plan = KdPlan::Scan;
    return s;
  }

  s.abs_slack = kKdExtentSlack * max_extent / max_dir;
  bool float_ok = s.abs_slack >= 0x1p-100 && s.abs_slack <= 0x1p64;
  double t0 = double(ray.tnear), t1 = double(ray.tfar);
  t0 -= slack(t0, s.abs_slack);
  t1 += slack(t1, s.abs_slack);
  for (int a = 0; a < 3; ++a) {
    const double org = ray.org[a], dir = ray.dir[a];
    s.parallel[a] = dir == 0.0;
    s.negative[a] = dir < 0.0;
    s.inv_dir[a] = s.parallel[a] ? 0.0 : 1.0 / dir;
    const double lo = tree.bounds.lo[a], hi = tree.bounds.hi[a];
    if (s.parallel[a]) {
      if (org < lo || org > hi) return s;
      continue;
    }
    // Split planes lie in the scene box, so |split - org| <= `reach` on this axis.
    const double reach = max_of(std::fabs(org - lo), std::fabs(org - hi));
    float_ok = float_ok && std::fabs(dir) >= 0x1p-64 && reach * std::fabs(s.inv_dir[a]) <= 0x1p64;
    double ta = (lo - org) * s.inv_dir[a], tb = (hi - org) * s.inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = max_of(t0, ta - slack(ta, s.abs_slack));
    t1 = min_of(t1, tb + slack(tb, s.abs_slack));
  }
  if (!(t0 <= t1)) return s;
  s.plan = KdPlan::Traverse;
  s.t0 = t0;
  s.t1 = t1;
  s.float_ok = float_ok && std::fabs(t0) <= 0x1p66 && std::fabs(t1) <= 0x1p66;
  if (s.float_ok) {
    for (int a = 0; a < 3; ++a) s.inv_dir_f[a] = static_cast<float>(s.inv_dir[a]);
    s.abs_slack_f = static_cast<float>(s.abs_slack);
    s.t0_f = round_float(t0, true);
    s.t1_f = round_float(t1, false);
  }
  return s;
}

Hit kd_scan_intersect(const KdTreeView& tree, const Ray& ray) {
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

bool kd_scan_occluded(const KdTreeView& tree, const Ray& ray) {
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

bool kd_slot_hit(const KdTreeView& tree, const Ray& ray, std::uint32_t slot, float limit, float out_tuv[3]) {
  const WatertightRay wr(ray);
  glm::vec3 v[3];
  load_triangle(tree, slot, v);
  TriangleHit th;
  if (!intersect_watertight(wr, v[0], v[1], v[2], limit, th)) return false;
  out_tuv[0] = th.t;
  out_tuv[1] = th.u;
  out_tuv[2] = th.v;
  return true;
}

KdKernels select_kd_kernels(Isa isa) {
  if (isa == Isa::Scalar) return scalar::kd_kernels();
#if defined(__x86_64__) || defined(_M_X64)
  if (isa == Isa::Sse4) return sse4::kd_kernels();
  if (isa == Isa::Avx2) return avx2::kd_kernels();
  if (isa == Isa::Avx512) return avx512::kd_kernels();
#endif
  throw std::invalid_argument("kd-tree: this build has no traversal kernels for the " + std::string(isa_name(isa)) +
                              " instruction set");
}

}  // namespace lancer
