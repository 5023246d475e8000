// Shared helpers of the kd-tree tests: ray generators and the comparison with the oracle.
#pragma once

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "accel/ray_offset.h"
#include "simd/isa.h"
#include "simd/splitmix64.h"

namespace lancer::test {

// The kd-tree tests that compare with the oracle run once per ISA (its traversal kernels
// and its leaf block width), named e.g. AllIsas/KdVsOracle.SmallRandomSoup/avx2; an ISA
// this CPU lacks is skipped with a message. Each ISA gets its own rays (isa_seed).
class KdIsaTest : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!cpu_supports(GetParam())) GTEST_SKIP() << "this CPU does not support " << isa_name(GetParam());
  }
  Isa isa() const { return GetParam(); }
  std::uint64_t isa_seed() const { return 0x10001ull * static_cast<std::uint64_t>(GetParam()); }
};

inline std::vector<Isa> kd_test_isas() { return {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512}; }

inline std::string kd_isa_param_name(const ::testing::TestParamInfo<Isa>& info) {
  return std::string(isa_name(info.param));
}

// Test rays and scenes from splitmix64: the same stream on every platform.
class TestRng : public SplitMix64 {
 public:
  explicit TestRng(std::uint64_t seed) : SplitMix64(seed) {}
  using SplitMix64::uniform;  // [0, 1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }
  glm::vec3 in_box(const Bounds3& b) {
    return {uniform(b.lo.x, b.hi.x), uniform(b.lo.y, b.hi.y), uniform(b.lo.z, b.hi.z)};
  }
  glm::vec3 direction() {
    for (;;) {
      const glm::vec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const float l2 = d.x * d.x + d.y * d.y + d.z * d.z;
      if (l2 > 1e-4f && l2 <= 1.0f) return d;
    }
  }
};

// `count` triangles with corners in `box` (flat boxes give flat scenes), each corner within
// `max_edge` of the first one on every axis. Zero-area triangles are possible and kept.
inline TriangleSoA random_soup(std::size_t count, std::uint64_t seed, const Bounds3& box, float max_edge) {
  TestRng rng(seed);
  TriangleSoA t;
  auto clamp_to_box = [&](glm::vec3 p) {
    for (int a = 0; a < 3; ++a) p[a] = p[a] < box.lo[a] ? box.lo[a] : (p[a] > box.hi[a] ? box.hi[a] : p[a]);
    return p;
  };
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 a = rng.in_box(box);
    const glm::vec3 b = clamp_to_box(a + max_edge * glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    const glm::vec3 c = clamp_to_box(a + max_edge * glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    t.push_back(a, b, c);
  }
  return t;
}

// `b` grown by `factor` times its extent on every side (a flat axis grows like the
// largest one), so ray origins can lie outside the scene at any scale.
inline Bounds3 grown(const Bounds3& b, float factor) {
  glm::vec3 e = b.extent() * factor;
  const float largest = std::fmax(e.x, std::fmax(e.y, e.z));
  for (int a = 0; a < 3; ++a)
    if (e[a] == 0.0f) e[a] = largest > 0.0f ? largest : 1.0f;
  return {b.lo - e, b.hi + e};
}

// A random point on a random triangle.
inline glm::vec3 point_on_triangle(const TriangleSoA& t, TestRng& rng) {
  const std::uint32_t i = rng.below(static_cast<std::uint32_t>(t.size()));
  float u = rng.uniform(), v = rng.uniform();
  if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
  return t.vertex(i, 0) * (1.0f - u - v) + t.vertex(i, 1) * u + t.vertex(i, 2) * v;
}

// A vertex coordinate of a random triangle: rays through it hit edges and vertices exactly.
inline glm::vec3 random_vertex(const TriangleSoA& t, TestRng& rng) {
  return t.vertex(rng.below(static_cast<std::uint32_t>(t.size())), static_cast<int>(rng.below(3)));
}

// The ray kinds the comparison covers. Each generator is deterministic in (seed, index).
enum class RayKind {
  Random,         // origin around the scene, random direction (many misses)
  Aimed,          // from outside towards a point on a triangle
  Inside,         // origin inside the scene box
  AxisParallel,   // direction +-e_axis, origin at a vertex coordinate or random
  InSplitPlane,   // lying in an actual split plane of the tree
  FromSplitPlane, // starting on an actual split plane
  Segment,        // finite [tnear, tfar) through the scene
};

inline const char* ray_kind_name(RayKind k) {
  switch (k) {
    case RayKind::Random: return "random";
    case RayKind::Aimed: return "aimed";
    case RayKind::Inside: return "inside";
    case RayKind::AxisParallel: return "axis-parallel";
    case RayKind::InSplitPlane: return "in-split-plane";
    case RayKind::FromSplitPlane: return "from-split-plane";
    case RayKind::Segment: return "segment";
  }
  return "?";
}

// Split planes (axis, position) of the tree's inner nodes.
struct SplitPlane {
  int axis;
  float pos;
};
inline std::vector<SplitPlane> split_planes(const KdTree& tree) {
  std::vector<SplitPlane> out;
  for (const KdNode& n : tree.nodes())
    if (!n.is_leaf()) out.push_back({n.axis(), n.split()});
  return out;
}

inline Ray make_ray(RayKind kind, const TriangleSoA& tris, const Bounds3& box, const std::vector<SplitPlane>& planes,
                    TestRng& rng) {
  Ray r;
  const Bounds3 outer = grown(box, 0.5f);
  switch (kind) {
    case RayKind::Random:
      r.org = rng.in_box(outer);
      r.dir = rng.direction();
      break;
    case RayKind::Aimed:
      r.org = rng.in_box(outer);
      r.dir = point_on_triangle(tris, rng) - r.org;
      break;
    case RayKind::Inside:
      r.org = rng.in_box(box);
      r.dir = rng.direction();
      break;
    case RayKind::AxisParallel: {
      const int axis = static_cast<int>(rng.below(3));
      r.org = rng.below(2) ? random_vertex(tris, rng) : point_on_triangle(tris, rng);
      if (rng.below(4) == 0) r.org[(axis + 1) % 3] = random_vertex(tris, rng)[(axis + 1) % 3];
      r.org[axis] = rng.below(2) ? outer.lo[axis] : outer.hi[axis];
      r.dir = glm::vec3(0.0f);
      r.dir[axis] = r.org[axis] == outer.lo[axis] ? 1.0f : -1.0f;
      if (rng.below(3) == 0) r.org[axis] = rng.uniform(box.lo[axis], box.hi[axis]);  // start inside
      break;
    }
    case RayKind::InSplitPlane:
    case RayKind::FromSplitPlane: {
      if (planes.empty()) return make_ray(RayKind::Inside, tris, box, planes, rng);
      const SplitPlane p = planes[rng.below(static_cast<std::uint32_t>(planes.size()))];
      r.org = rng.below(2) ? rng.in_box(outer) : point_on_triangle(tris, rng);
      r.org[p.axis] = p.pos;
      r.dir = rng.below(2) ? rng.direction() : point_on_triangle(tris, rng) - r.org;
      if (kind == RayKind::InSplitPlane) {
        r.dir[p.axis] = 0.0f;
        if (rng.below(4) == 0) r.dir[(p.axis + 1) % 3] = 0.0f;  // axis-parallel and in the plane
      }
      break;
    }
    case RayKind::Segment:
      r.org = rng.in_box(outer);
      r.dir = point_on_triangle(tris, rng) - r.org;
      r.tnear = rng.uniform(0.0f, 0.9f);
      r.tfar = r.tnear + rng.uniform(0.0f, 0.3f);
      break;
  }
  if (r.dir == glm::vec3(0.0f)) r.dir = {0.0f, 0.0f, 1.0f};
  for (int a = 0; a < 3; ++a)  // aimed at a non-finite triangle: aim at the box instead
    if (!std::isfinite(r.org[a]) || !std::isfinite(r.dir[a])) {
      r.org = rng.in_box(outer);
      r.dir = rng.in_box(box) - r.org;
      break;
    }
  return r;
}

// A pinhole camera; rays are not normalised (t in units of the pixel direction).
struct Pinhole {
  glm::vec3 eye, forward, right, up;  // right and up span one pixel

  static Pinhole looking_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up_hint, float fov_deg, int width) {
    const glm::vec3 f = glm::normalize(target - eye);
    const glm::vec3 r = glm::normalize(glm::cross(f, up_hint));
    const glm::vec3 u = glm::cross(r, f);
    const float pixel = 2.0f * std::tan(fov_deg * 0.5f * 3.14159265f / 180.0f) / float(width);
    return {eye, f, r * pixel, u * pixel};
  }
  Ray ray(int px, int py, int width, int height) const {
    Ray r;
    r.org = eye;
    r.dir = forward + right * (float(px) + 0.5f - 0.5f * float(width)) + up * (0.5f * float(height) - float(py) - 0.5f);
    return r;
  }
};

// The 8x8 pixel tiles of a width x height image, each tile's rays in row order.
inline std::vector<std::vector<Ray>> camera_tiles(const Pinhole& cam, int width, int height) {
  std::vector<std::vector<Ray>> tiles;
  for (int ty = 0; ty < height; ty += 8)
    for (int tx = 0; tx < width; tx += 8) {
      std::vector<Ray> t;
      for (int y = ty; y < ty + 8; ++y)
        for (int x = tx; x < tx + 8; ++x) t.push_back(cam.ray(x, y, width, height));
      tiles.push_back(std::move(t));
    }
  return tiles;
}

inline std::string describe(const Ray& r) {
  std::ostringstream s;
  s.precision(9);
  s << "org (" << r.org.x << ", " << r.org.y << ", " << r.org.z << ") dir (" << r.dir.x << ", " << r.dir.y << ", "
    << r.dir.z << ") t [" << r.tnear << ", " << r.tfar << ")";
  return s.str();
}

inline bool same_hit(const Hit& a, const Hit& b) {
  return a.prim == b.prim && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
         std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
         std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

// Compares closest hit (same triangle, bit-identical t, u, v) and any hit for every ray,
// and, when `secondary` is set, also a ray from each hit point (once from the exact hit
// point with tnear 0, once offset along the normal). Runs the rays in parallel.
struct OracleComparison {
  std::atomic<std::size_t> rays{0}, hits{0}, mismatches{0};
  std::mutex mutex;
  std::vector<std::string> first_failures;

  void check(const Accelerator& kd, const Accelerator& oracle, const Ray& r) {
    const Hit a = kd.intersect(r), b = oracle.intersect(r);
    const bool oa = kd.occluded(r), ob = oracle.occluded(r);
    ++rays;
    if (b.valid()) ++hits;
    if (same_hit(a, b) && oa == ob) return;
    ++mismatches;
    std::lock_guard<std::mutex> lock(mutex);
    if (first_failures.size() < 8) {
      std::ostringstream s;
      s.precision(9);
      s << describe(r) << ": kd prim " << a.prim << " t " << a.t << " occluded " << oa << "; oracle prim " << b.prim
        << " t " << b.t << " occluded " << ob;
      first_failures.push_back(s.str());
    }
  }

  void expect_no_mismatch(const std::string& what) {
    std::string all;
    for (const std::string& f : first_failures) all += "\n  " + f;
    EXPECT_EQ(mismatches.load(), 0u) << what << ": " << mismatches << " of " << rays << " rays differ" << all;
  }
};

inline void compare_with_oracle(const KdTree& kd, const TriangleSoA& tris, RayKind kind, std::size_t count,
                                std::uint64_t seed, bool secondary, OracleComparison& cmp) {
  const BruteForce oracle(tris);
  const Bounds3 box = kd.bounds();  // finite even when some triangles are not
  const std::vector<SplitPlane> planes = split_planes(kd);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      TestRng rng(seed * 0x100000001B3ull + i);
      const Ray r = make_ray(kind, tris, box, planes, rng);
      cmp.check(kd, oracle, r);
      if (!secondary) continue;
      const Hit h = oracle.intersect(r);
      if (!h.valid()) continue;
      Ray s;
      s.org = r.org + h.t * r.dir;  // exactly as a renderer would compute it, no offset
      s.dir = rng.direction();
      cmp.check(kd, oracle, s);
      const glm::vec3 e1 = tris.vertex(h.prim, 1) - tris.vertex(h.prim, 0);
      const glm::vec3 e2 = tris.vertex(h.prim, 2) - tris.vertex(h.prim, 0);
      glm::vec3 n(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x);
      const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
      if (!(len > 0.0f)) continue;
      n /= len;
      if (n.x * r.dir.x + n.y * r.dir.y + n.z * r.dir.z > 0.0f) n = -n;
      s.org = offset_ray_origin(s.org, n);
      s.dir = rng.direction();
      if (s.dir.x * n.x + s.dir.y * n.y + s.dir.z * n.z < 0.0f) s.dir = -s.dir;
      cmp.check(kd, oracle, s);
    }
  });
}

}  // namespace lancer::test
