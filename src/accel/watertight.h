// Scalar watertight ray/triangle intersection.
//
// Follows Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
// The ray is sheared so it runs along +z from the origin; the triangle's 2D edge functions
// U, V, W are then evaluated in that space. A ray through a shared edge or vertex sees
// U, V or W exactly 0 on both triangles, so it cannot slip between them. When an edge
// function is exactly 0 in single precision it is recomputed in double precision, as the
// paper does, so the sign decision is exact (a nonzero float edge function has the exact
// sign already: rounding is monotone); unlike the paper, that case then stays in double.
//
// Invariants: no back-face culling; a hit counts when tnear <= t < tmax; a degenerate
// (zero-area in the projection) triangle never hits.
#pragma once

#include <cmath>
#include <utility>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"

namespace lancer {

// Per-ray constants of the shear transform, computed once per ray.
struct WatertightRay {
  glm::vec3 org;
  int kx, ky, kz;      // permutation: kz is the dominant axis of dir
  float sx, sy, sz;    // shear constants
  float tnear;

  explicit WatertightRay(const Ray& r) : org(r.org), tnear(r.tnear) {
    const glm::vec3 a = glm::abs(r.dir);
    kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (r.dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the projected triangle
    sx = r.dir[kx] / r.dir[kz];
    sy = r.dir[ky] / r.dir[kz];
    sz = 1.0f / r.dir[kz];
  }
};

struct TriangleHit {
  float t, u, v;
};

// Returns true and fills `out` when the ray hits triangle (a, b, c) with tnear <= t < tmax.
inline bool intersect_watertight(const WatertightRay& r, const glm::vec3& a, const glm::vec3& b,
                                 const glm::vec3& c, float tmax, TriangleHit& out) {
  const glm::vec3 A = a - r.org, B = b - r.org, C = c - r.org;
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];

  const float U = cx * by - cy * bx;
  const float V = ax * cy - ay * cx;
  const float W = bx * ay - by * ax;
  const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
    // The products are exact in double, so these are the exact signs of the edge functions
    // of the sheared float corners. The paper rounds them back to float, which turns a
    // value below half the least subnormal into 0: a projected triangle of zero area (edge
    // functions of mixed signs) could then pass the sign test as {0, 0, +tiny} and report
    // a hit anywhere on the ray's line. So this rare case finishes in double.
    const double Ud = double(cx) * double(by) - double(cy) * double(bx);
    const double Vd = double(ax) * double(cy) - double(ay) * double(cx);
    const double Wd = double(bx) * double(ay) - double(by) * double(ax);
    if ((Ud < 0.0 || Vd < 0.0 || Wd < 0.0) && (Ud > 0.0 || Vd > 0.0 || Wd > 0.0)) return false;
    const double det = Ud + Vd + Wd;
    if (det == 0.0) return false;
    const float t = static_cast<float>((Ud * double(az) + Vd * double(bz) + Wd * double(cz)) / det);
    if (!(t >= r.tnear && t < tmax)) return false;
    out = {t, static_cast<float>(Vd / det), static_cast<float>(Wd / det)};
    return true;
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;

  const float det = U + V + W;
  if (det == 0.0f) return false;

  const float T = U * az + V * bz + W * cz;
  const float t = T / det;
  if (!(t >= r.tnear && t < tmax)) return false;  // also rejects NaN

  const float inv = 1.0f / det;
  out = {t, V * inv, W * inv};
  return true;
}

}  // namespace lancer
