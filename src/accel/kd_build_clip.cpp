#include "accel/kd_build_clip.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace lancer::kd {
namespace {

struct Vec3d {
  double v[3];
};

// A convex polygon: the triangle plus at most one new vertex per clipping plane.
struct Polygon {
  Vec3d p[9 + 3];
  int n = 0;
};

// Keeps the part of `in` with sign * (x[axis] - c) >= 0. Points on the plane are kept, and
// new vertices get exactly `c` on the clipping axis.
void clip_against_plane(const Polygon& in, int axis, double c, double sign, Polygon& out) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const Vec3d& a = in.p[i];
    const Vec3d& b = in.p[(i + 1) % in.n];
    const double da = sign * (a.v[axis] - c), db = sign * (b.v[axis] - c);
    if (da >= 0.0) out.p[out.n++] = a;
    if ((da >= 0.0) != (db >= 0.0)) {
      const double t = da / (da - db);  // da and db differ in sign: no division by zero
      Vec3d q;
      for (int k = 0; k < 3; ++k) q.v[k] = a.v[k] + t * (b.v[k] - a.v[k]);
      q.v[axis] = c;
      out.p[out.n++] = q;
    }
  }
}

float round_down(double d) {
  float f = static_cast<float>(d);
  if (double(f) > d) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return std::nextafter(f, -std::numeric_limits<float>::infinity());  // one more ulp of margin
}

float round_up(double d) {
  float f = static_cast<float>(d);
  if (double(f) < d) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return std::nextafter(f, std::numeric_limits<float>::infinity());
}

}  // namespace

Bounds3 clipped_triangle_bounds(const TriangleSoA& tris, std::uint32_t tri, const Bounds3& cell) {
  const Bounds3 tri_box = tris.triangle_bounds(tri);
  Bounds3 clamped;
  for (int k = 0; k < 3; ++k) {
    clamped.lo[k] = std::max(tri_box.lo[k], cell.lo[k]);
    clamped.hi[k] = std::min(tri_box.hi[k], cell.hi[k]);
  }
  if (clamped.empty()) return Bounds3{};

  Polygon polygons[2];
  Polygon* cur = &polygons[0];
  Polygon* next = &polygons[1];
  cur->n = 3;
  for (int k = 0; k < 3; ++k) cur->p[k] = {{tris.x[k][tri], tris.y[k][tri], tris.z[k][tri]}};
  for (int axis = 0; axis < 3; ++axis) {
    // Planes the triangle does not cross cut nothing: skip them (exact, and faster).
    if (tri_box.lo[axis] < cell.lo[axis]) {
      clip_against_plane(*cur, axis, cell.lo[axis], 1.0, *next);
      std::swap(cur, next);
    }
    if (tri_box.hi[axis] > cell.hi[axis]) {
      clip_against_plane(*cur, axis, cell.hi[axis], -1.0, *next);
      std::swap(cur, next);
    }
    if (cur->n == 0) return Bounds3{};
  }
  const Polygon& a = *cur;

  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -lo[k];
  }
  for (int i = 0; i < a.n; ++i)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], a.p[i].v[k]);
      hi[k] = std::max(hi[k], a.p[i].v[k]);
    }
  Bounds3 out;
  for (int k = 0; k < 3; ++k) {
    out.lo[k] = std::max(round_down(lo[k]), clamped.lo[k]);
    out.hi[k] = std::min(round_up(hi[k]), clamped.hi[k]);
  }
  return out;
}

}  // namespace lancer::kd
