// Robust origins for secondary rays.
//
// Two offsets along the geometric normal:
//  - offset_ray_origin(p, n) follows Wächter & Binder, "A Fast and Robust Method for
//    Avoiding Self-Intersection", Ray Tracing Gems, chapter 6, 2019: 256 float ulps of each
//    coordinate of p, and 2^-16 absolutely near the origin. It knows neither the triangle
//    nor the ray, so it serves points with no better error model (a light sample, a hit
//    point computed as org + t * dir); its constants are empirical, it can be too large
//    (biasing what the ray sees) and, for a large triangle, too small.
//  - offset_ray_origin(p, n, dir, triangle) is what the integrators use: the origin for a
//    ray of direction `dir` leaving the point p of `triangle`, lifted just far enough that
//    the watertight kernel provably cannot report that triangle again. Derived below.
//
// Why a ray can re-hit the triangle it leaves. The exact ray from an origin o at height
// H > 0 above the triangle's plane meets the plane behind it, at t* = -H / (n . d) < 0, and
// a hit needs t >= tnear = 0. Three things stand between: p itself is off the plane by its
// rounding to float (up to u |p_k| per axis, u = 2^-24: surface.cpp sums the barycentrics
// in double, so only that final rounding counts), o is rounded again, and the kernel
// computes t with errors (watertight.h: Woop, Benthin & Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2013, which the kd-tree's single-ray and packet paths reproduce bit
// for bit). The first two are measured: the height of the float o above the plane is
// computed in double. For the third, with A_i = v_i - o the vertices relative to o:
//   X_i = A_i.kx - sx A_i.kz,  Y_i = A_i.ky - sy A_i.kz,  Z_i = sz A_i.kz,
//   U, V, W = 2x2 cross products of the (X, Y),  t = (U Z_0 + V Z_1 + W Z_2) / (U + V + W).
// Its errors split in two (bounds in the style of the conservative triangle test of pbrt-v3,
// Pharr, Jakob & Humphreys 2016, 3.9.6, with gamma_k = k u / (1 - k u)):
//  1. Roundings made once per vertex (A, the shear products and differences, Z): the kernel
//     then works exactly on a triangle whose vertex i moved along n by at most
//       delta_i = gamma_2 (|n_kz||A_kz| + |n_kx|(|A_kx| + |X_i| + |sx A_kz|) + same for ky),
//     so the plane it sees lies within s = max delta_i of the true one where the ray's line
//     crosses it, times B, the sum of that crossing's |barycentrics| (1 inside).
//  2. Roundings that differ per edge: each of U, V, W is off by at most
//     e = gamma_2 (|X Y'| + |Y X'|), E in all. Then t is the average of the Z_i with the
//     computed barycentrics, and it moves from the true crossing by at most
//     E (max |Z_i| + |t*|) / D, with D = |U + V + W| - E a lower bound on the kernel's
//     determinant; the three products and sums in the numerator add gamma_3 max |Z_i|.
// With r = E / D, t < 0 (no hit) is certain once
//       H (1 - r) > s B (1 + r) + (n . d) ((r + gamma_3) max |Z_i| + underflow / D).
// The terms scale with |v_i - o|, the triangle's extent around p (not its distance from the
// world origin), and depend on the ray: along the normal of an axis-aligned plane they
// vanish (every Z_i is -H / d_kz), so any positive H is enough. As the ray nears the plane
// D shrinks like 2 area |n . d|; within about u extent^2 / area of tangent no height makes
// t provably negative, but there the line crosses the plane far behind, outside the
// triangle, and a second proof takes over: two of U, V, W of opposite signs beyond their
// errors, and the kernel reports no hit whatever t is. That proof is not used elsewhere: a
// line that misses the triangle just past an edge crosses the neighbour there (in a mesh),
// which needs about the height the first proof gives for a crossing inside (B = 1).
//
// The origin is chosen by trying a height, evaluating that bound for the very float origin
// and direction the ray will have, and growing the height until the bound holds: typically
// 5 to 20 ulps of the triangle's extent for a tilted triangle; for an axis-aligned one, a
// ray whose largest component is along the normal gets the least step the plane's
// coordinate allows (2^-64 at 0), the others a few ulps of the extent. The bound is for
// the triangle the ray leaves; a coplanar neighbour of similar size and shape sees errors of
// the same size (and the tests find none hit), and one across a convex edge is guarded only
// by the angle between them.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec3.hpp>

#include "accel/instances.h"
#include "accel/triangle_soa.h"

namespace lancer {

// `n` is the geometric normal, facing the side the new ray leaves from.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n) {
  constexpr float kOriginZone = 1.0f / 32.0f;  // below this |coordinate|, offset absolutely
  constexpr float kFloatScale = 1.0f / 65536.0f;
  constexpr float kIntScale = 256.0f;
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(p[i]) < kOriginZone) {  // near 0 ulps are too small to move by (and -0 + -k overflows)
      out[i] = p[i] + kFloatScale * n[i];
      continue;
    }
    const auto ulps = static_cast<std::int32_t>(kIntScale * n[i]);
    const auto bits = std::bit_cast<std::int32_t>(p[i]);
    out[i] = std::bit_cast<float>(bits + (p[i] < 0.0f ? -ulps : ulps));
  }
  return out;
}

using TriangleCorners = std::array<glm::vec3, 3>;

namespace ray_offset_batch {
struct Lanes;
}

inline TriangleCorners triangle_corners(const TriangleSoA& t, std::size_t i) {
  return {t.vertex(i, 0), t.vertex(i, 1), t.vertex(i, 2)};
}

namespace ray_offset_detail {

inline constexpr double kUnit = 0x1p-24;  // float unit roundoff
inline constexpr double gamma(int k) { return k * kUnit / (1.0 - k * kUnit); }
// Absolute error of a float operation whose result falls below the normal range.
inline constexpr double kSubnormalError = 0x1p-148;
// The least height tried: keeps the kernel's t (about H / (n . d)) and its products normal.
inline constexpr double kMinHeight = 0x1p-64;
inline constexpr double kInfinite = std::numeric_limits<double>::infinity();

// Component k of v. glm's operator[] is a switch on k: with the shear's axes known only at
// run time, a branch per access (a quarter of required_height's instructions). glm::value_ptr
// is glm's own view of the three components as an array.
inline float component(const glm::vec3& v, int k) { return glm::value_ptr(v)[k]; }
inline double component(const glm::dvec3& v, int k) { return glm::value_ptr(v)[k]; }

// The kernel's shear for a ray direction d and one choice of its dominant axis kz
// (watertight.h's WatertightRay, less the swap of kx and ky, which changes no magnitude),
// and n . d' for the ray it then traces, d' = (sx, sy, 1) / sz on the axes (kx, ky, kz).
struct Shear {
  int kx, ky, kz;
  float sx, sy, sz;
  double nd;
};

inline Shear make_shear(const glm::vec3& d, const glm::dvec3& n, int kz) {
  Shear sh;
  sh.kz = kz;
  sh.kx = kz == 2 ? 0 : kz + 1;
  sh.ky = sh.kx == 2 ? 0 : sh.kx + 1;
  const float dz = component(d, kz);
  sh.sx = component(d, sh.kx) / dz;
  sh.sy = component(d, sh.ky) / dz;
  sh.sz = 1.0f / dz;
  sh.nd = (component(n, sh.kx) * double(sh.sx) + component(n, sh.ky) * double(sh.sy) + component(n, kz)) /
          double(sh.sz);
  return sh;
}

// The height above the plane of triangle v (unit normal n, facing the side the ray leaves
// to) that origin o needs so the kernel cannot report v for this ray (the bound at the top
// of this file): near tangent, 0 when the kernel provably sees the ray's line miss v, and
// +inf when neither proof holds.
inline double required_height(const TriangleCorners& v, const glm::vec3& o, const glm::dvec3& n, const Shear& sh) {
  double X[3], Y[3], z_max = 0.0, s = 0.0;
  const float ox = component(o, sh.kx), oy = component(o, sh.ky), oz = component(o, sh.kz);
  const double n_kx = component(n, sh.kx), n_ky = component(n, sh.ky), n_kz = component(n, sh.kz);
  for (int i = 0; i < 3; ++i) {
    // The kernel's float operations, in its order.
    const float ax = component(v[i], sh.kx) - ox, ay = component(v[i], sh.ky) - oy, az = component(v[i], sh.kz) - oz;
    const float x = ax - sh.sx * az, y = ay - sh.sy * az, z = sh.sz * az;
    X[i] = x;
    Y[i] = y;
    z_max = std::max(z_max, double(std::fabs(z)));
    const double shift = std::fabs(n_kz * az) +
                         std::fabs(n_kx) * (std::fabs(ax) + std::fabs(x) + std::fabs(double(sh.sx) * az)) +
                         std::fabs(n_ky) * (std::fabs(ay) + std::fabs(y) + std::fabs(double(sh.sy) * az));
    s = std::max(s, shift);
  }
  s = gamma(2) * s + 3.0 * kSubnormalError;
  // Edge functions of the float (X, Y) (products exact in double), and the kernel's error.
  double e[3], err[3];
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1, k = j == 2 ? 0 : j + 1;  // U: (1, 2), V: (2, 0), W: (0, 1)
    const double p1 = X[k] * Y[j], p2 = Y[k] * X[j];
    e[i] = p1 - p2;
    err[i] = gamma(2) * (std::fabs(p1) + std::fabs(p2)) + 3.0 * kSubnormalError;
  }
  // The second proof: two edge functions of opposite signs beyond their errors, and the
  // kernel cannot report a hit whatever the height.
  const bool some_positive = e[0] > err[0] || e[1] > err[1] || e[2] > err[2];
  const bool some_negative = e[0] < -err[0] || e[1] < -err[1] || e[2] < -err[2];
  const bool misses = some_positive && some_negative;
  const double E = err[0] + err[1] + err[2];
  const double sum = std::fabs(e[0] + e[1] + e[2]);
  const double D = sum * (1.0 - 0x1p-50) - E;  // a lower bound on the kernel's |U + V + W|
  if (!(sh.nd > 0.0) || !(D > 2.0 * E) || !std::isfinite(sh.nd))  // r = E / D >= 1/2: near tangent
    return misses ? 0.0 : kInfinite;
  // B, the sum of |barycentrics| of the line's crossing. A line that misses v crosses a
  // neighbour instead (a mesh continues past the edge), which asks about the height v asks
  // for a crossing inside it: B = 1 then, not the miss's 0.
  const double B = misses ? 1.0 : (std::fabs(e[0]) + std::fabs(e[1]) + std::fabs(e[2])) * (1.0 + 0x1p-50) / sum;
  z_max *= 1.0 + gamma(1);
  // H (1 - r) > s B (1 + r) + (n . d') ((r + gamma_3) max|Z| + underflow / D), times D.
  const double need =
      (s * B * (D + E) + sh.nd * ((E + gamma(3) * D) * z_max + 8.0 * kSubnormalError)) / (D - E);
  return need * (1.0 + 0x1p-20);  // the roundings of this evaluation itself
}

}  // namespace ray_offset_detail

// Origins for rays leaving one hit point p of triangle `tri`, in any direction: the point
// pushed along the triangle's normal, to the side the ray leaves to, just far enough that
// the ray cannot hit `tri` again (see the top of this file). p should lie on the triangle up
// to its rounding to float (make_surface_point sums the barycentrics in double); its actual
// distance from the plane is measured and made up for, whatever it is. `n` is the geometric
// normal in either orientation; it only decides the side for a ray exactly in the plane.
// A triangle without area, or a non-finite input, gets offset_ray_origin(p, n).
//
// A triangle drawn through an instance (`inst` not null): `tri` is in the instance's
// space, p and n in world space, and the bound is proven for the ray as the two-level
// accelerator traces it: the world origin returned, moved into the instance's space by
// ray_to_object's very float operations, with the direction moved likewise.
class SurfaceOffset {
 public:
  //
  // `time`: where in the shutter the rays leave (Ray::time, kept for the shadow rays made
  // from this offset); `inst` must be the instance as it is at that time (instance_at).
  // Construction only keeps the inputs: the plane in double (Plane) is made when a ray is
  // solved here, and the batch solvers (ray_offset_batch.h) make it themselves, per lane,
  // with the very same operations.
  SurfaceOffset(const glm::vec3& p, const glm::vec3& n, const TriangleCorners& tri, const Instance* inst = nullptr,
                float time = 0.0f)
      : tri_(tri),
        p_(inst ? to_object_point(*inst, p) : p),
        n_(n),
        p_world_(p),
        inst_(inst ? std::optional<Instance>(*inst) : std::nullopt),
        time_(time) {}

  // The origin for a ray of direction `dir`, which must be exactly the direction the ray is
  // traced with (the bound follows the kernel's arithmetic on it). A ray within about 1e-6
  // of tangent may need up to |n . dir| times the distance its line takes to leave the
  // triangle.
  float time() const { return time_; }

  glm::vec3 origin(const glm::vec3& dir) const {
    return solve(dir, [&](const glm::vec3&) { return dir; });
  }

  // The origin o for a segment to `end`, traced with direction end - o (in float, as the
  // caller computes it): a shadow ray that must reach its end point whatever the height.
  glm::vec3 origin_towards(const glm::vec3& end) const {
    return solve(end - p_world_, [&](const glm::vec3& o) { return end - o; });
  }

  // Lays out the ray origin(target) (origin_towards(target) when towards) as lane i of a
  // batch solver: the triangle, the point, the normal and the target, from which the solver
  // makes the plane and the first attempt as plane() and start() do. False when the ray
  // must be solved here (a triangle drawn through an instance: ray_offset_batch.cpp).
  bool fill_lane(const glm::vec3& target, bool towards, ray_offset_batch::Lanes& lanes, int i) const;

 private:
  // The triangle's plane in double and what the bound needs of it at p.
  struct Plane {
    glm::dvec3 corner{0.0}, normal{0.0}, height_error_weights{0.0};
    double p_height = 0.0, p_height_error = 0.0, extent = 0.0, o_rounding = 0.0;
    bool valid = false;
  };

  // Made once, on the first ray solved here (a path's rays are solved in batches instead).
  // A cache in a const object: one SurfaceOffset must not be solved from two threads at once
  // (each integrator makes its own per hit; copies are independent).
  const Plane& plane() const {
    if (!plane_) plane_ = make_plane();
    return *plane_;
  }

  Plane make_plane() const {
    Plane pl;
    pl.corner = glm::dvec3(tri_[0]);
    // The plane in double. Differences of floats are exact there (or nearly), so each
    // component of the cross product is off by at most its two products' roundings: the
    // normal is good to a few 2^-53 per component, and exact for an axis-aligned plane.
    const glm::dvec3 e1 = glm::dvec3(tri_[1]) - pl.corner, e2 = glm::dvec3(tri_[2]) - pl.corner;
    const glm::dvec3 cross = glm::cross(e1, e2);
    const double len = std::sqrt(glm::dot(cross, cross));
    pl.valid = len > 0.0 && std::isfinite(len) && std::isfinite(p_world_.x + p_world_.y + p_world_.z);
    if (!pl.valid) return pl;
    const double inv_len = 1.0 / len;
    pl.normal = cross * inv_len;
    const glm::dvec3 products(std::fabs(e1.y * e2.z) + std::fabs(e1.z * e2.y),
                              std::fabs(e1.z * e2.x) + std::fabs(e1.x * e2.z),
                              std::fabs(e1.x * e2.y) + std::fabs(e1.y * e2.x));
    const glm::dvec3 normal_error = (0x1p-51 * inv_len) * products + 0x1p-50 * glm::abs(pl.normal);
    pl.height_error_weights = normal_error + 0x1p-50 * glm::abs(pl.normal);
    const glm::dvec3 rel = glm::dvec3(p_) - pl.corner;
    pl.p_height = glm::dot(rel, pl.normal);
    pl.p_height_error = glm::dot(glm::abs(rel), pl.height_error_weights);
    for (int k = 0; k < 3; ++k) {
      for (const glm::vec3& v : tri_) pl.extent = std::max(pl.extent, std::fabs(double(v[k]) - p_[k]));
      pl.o_rounding += 2.0 * ray_offset_detail::gamma(1) * std::fabs(pl.normal[k] * p_[k]);
    }
    if (inst_) pl.o_rounding += 2.0 * round_trip_error(*inst_, pl.normal);
    return pl;
  }

  // What solve knows before its first attempt, for a ray whose direction from p is `dir`:
  // the plane's normal on the ray's side, how far p may lie on the wrong side, the first
  // height. False when the bound does not apply (a triangle without area, an unusable dir).
  struct Start {
    glm::dvec3 normal{0.0};
    double deficit = 0.0, h = 0.0;
  };
  bool start(const Plane& pl, const glm::vec3& dir, Start& s) const {
    using namespace ray_offset_detail;
    if (!pl.valid || !usable(dir)) return false;
    const double toward = glm::dot(glm::dvec3(inst_ ? inst_->to_object.vector(dir) : dir), pl.normal);
    const bool flip = toward < 0.0 || (toward == 0.0 && glm::dot(glm::dvec3(n_), pl.normal) < 0.0);
    s.normal = flip ? -pl.normal : pl.normal;
    // How far p lies on the wrong side of the plane, at most.
    s.deficit = std::max(0.0, (flip ? pl.p_height : -pl.p_height) + pl.p_height_error);
    s.h = kMinHeight + 2.0 * s.deficit + pl.o_rounding;
    return true;
  }

  // The least height tried first, then grown until the bound holds for the ray from the
  // float origin o with direction dir_for(o); `dir` (the ray from p) picks the side.
  template <typename DirFor>
  glm::vec3 solve(const glm::vec3& dir, DirFor dir_for) const {
    using namespace ray_offset_detail;
    const Plane& pl = plane();
    Start st;
    if (!start(pl, dir, st)) return offset_ray_origin(p_world_, glm::dot(dir, n_) < 0.0f ? -n_ : n_);
    const glm::dvec3& normal = st.normal;
    const double deficit = st.deficit;
    double h = st.h;
    glm::vec3 o = p_, sheared(0.0f);
    Shear shears[3];
    int count = 0;
    for (int attempt = 0; attempt < 64; ++attempt) {
      o = glm::vec3(glm::dvec3(p_) + h * normal);
      // Through an instance: the world origin, and the origin and direction the kernel sees.
      const glm::vec3 world = inst_ ? inst_->to_world.point(o) : o;
      if (inst_) o = inst_->to_object.point(world);
      const glm::vec3 d = inst_ ? inst_->to_object.vector(dir_for(world)) : dir_for(o);
      if (!usable(d)) break;
      if (d != sheared) {
        // Every permutation the kernel could pick for d (a near tie may go either way).
        const glm::vec3 a = glm::abs(d);
        const float a_max = std::max(a.x, std::max(a.y, a.z));
        count = 0;
        for (int k = 0; k < 3; ++k)
          if (a[k] >= a_max * (1.0f - 0x1p-16f)) shears[count++] = make_shear(d, normal, k);
        sheared = d;
      }
      const glm::dvec3 rel = glm::dvec3(o) - pl.corner;
      const double have = glm::dot(rel, normal) - glm::dot(glm::abs(rel), pl.height_error_weights);
      double need = 0.0;
      for (int i = 0; i < count; ++i) need = std::max(need, required_height(tri_, o, normal, shears[i]));
      if (have > 0.0 && have >= need) return world;
      // Where no height is proven yet (a ray near tangent), grow from a few ulps of the extent.
      h = std::max(2.0 * h, std::isfinite(need) ? 1.25 * need + 2.0 * deficit + pl.o_rounding
                                                : gamma(4) * pl.extent);
    }
    return inst_ ? inst_->to_world.point(o) : o;  // not reached for finite input: the line leaves the triangle long before
  }

  // p in the instance's space, rounded once from a double evaluation.
  static glm::vec3 to_object_point(const Instance& inst, const glm::vec3& p) {
    const glm::dmat3 l(inst.to_object.linear);
    return glm::vec3(l * glm::dvec3(p) + glm::dvec3(inst.to_object.offset));
  }

  // How far, along the plane's normal, the trip of an origin near p to world space and back
  // (to_world, then to_object, each up to gamma_3 of its terms per component) may move it.
  double round_trip_error(const Instance& inst, const glm::dvec3& normal) const {
    using ray_offset_detail::gamma;
    const glm::dmat3 to_w = glm::dmat3(inst.to_world.linear), to_o = glm::dmat3(inst.to_object.linear);
    glm::dmat3 abs_w, abs_o;
    for (int c = 0; c < 3; ++c) {
      abs_w[c] = glm::abs(to_w[c]);
      abs_o[c] = glm::abs(to_o[c]);
    }
    const glm::dvec3 world = glm::abs(to_w * glm::dvec3(p_) + glm::dvec3(inst.to_world.offset));
    const glm::dvec3 world_error = gamma(3) * (abs_w * glm::abs(glm::dvec3(p_)) + glm::abs(glm::dvec3(inst.to_world.offset)));
    const glm::dvec3 back_error =
        abs_o * world_error + gamma(3) * (abs_o * (world + world_error) + glm::abs(glm::dvec3(inst.to_object.offset)));
    return glm::dot(glm::abs(normal), back_error);
  }

  static bool usable(const glm::vec3& d) {
    const float m = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
    return m > 0.0f && std::isfinite(m) && std::isfinite(d.x + d.y + d.z);
  }

  TriangleCorners tri_;
  glm::vec3 p_, n_;  // p_ in the triangle's space, n_ in world space
  glm::vec3 p_world_;
  // A copy (a moving instance's transform exists only for this time); none in world space.
  std::optional<Instance> inst_;
  float time_ = 0.0f;
  mutable std::optional<Plane> plane_;
};

// One ray's origin: SurfaceOffset(p, n, tri).origin(dir).
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n, const glm::vec3& dir,
                                   const TriangleCorners& tri) {
  return SurfaceOffset(p, n, tri).origin(dir);
}

}  // namespace lancer
