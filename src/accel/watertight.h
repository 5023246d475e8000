// Scalar watertight ray/triangle intersection.
//
// Follows Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
// The ray is sheared so it runs along +z from the origin; the triangle's 2D edge functions
// U, V, W are then evaluated in that space. A ray through a shared edge or vertex sees
// U, V or W exactly 0 on both triangles, so it cannot slip between them. When an edge
// function is exactly 0 in single precision it is recomputed in double precision, as the
// paper does, so the sign decision is exact for the common case.
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

  float U = cx * by - cy * bx;
  float V = ax * cy - ay * cx;
  float W = bx * ay - by * ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
    U = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
    V = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
    W = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;

  const float det = U + V + W;
  if (det == 0.0f) return false;

  const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
  const float T = U * az + V * bz + W * cz;
  const float t = T / det;
  if (!(t >= r.tnear && t < tmax)) return false;  // also rejects NaN

  const float inv = 1.0f / det;
  out = {t, V * inv, W * inv};
  return true;
}

}  // namespace lancer
