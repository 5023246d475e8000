// The batch surface solvers (surface_batch.h) against make_surface_point, one hit at a time:
// every ISA must give the very same point, normals and side, bit for bit, on triangles with
// and without stored normals, hit from either side, and leave to make_surface_point what it
// must (no hit, a hit through an instance, a triangle whose normal has no usable length).
// Runs per ISA (AllIsas/SurfaceBatch.<Test>/<isa>).
#include "render/surface_batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "render/surface.h"
#include "simd/isa.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

class SurfaceBatch : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!cpu_supports(GetParam())) GTEST_SKIP() << "this CPU does not support " << isa_name(GetParam());
  }
};

glm::vec3 unit(SplitMix64& rng) {
  for (;;) {
    const glm::vec3 v(2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f);
    const float l = glm::length(v);
    if (l > 0.1f && l <= 1.0f) return v / l;
  }
}

bool same(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Triangles of every size and place, half of them with stored normals (some of which cancel
// out where they are interpolated), a few too small for their normal to have a float length.
struct Case {
  Scene scene;
  std::vector<Ray> rays;
  std::vector<Hit> hits;
};

Case make_case(std::uint64_t seed, int count) {
  SplitMix64 rng(seed);
  Case c;
  c.scene.materials.emplace_back();
  for (int i = 0; i < count; ++i) {
    const float size = std::pow(10.0f, 6.0f * rng.uniform() - 3.0f);
    const glm::vec3 centre = std::pow(10.0f, 4.0f * rng.uniform() - 1.0f) * unit(rng);
    glm::vec3 t[3];
    for (glm::vec3& v : t) v = centre + size * unit(rng);
    if (i % 50 == 7) t[2] = t[1] + glm::vec3(0.0f, 1e-30f, 0.0f) , t[1] = t[0];  // no usable normal length
    c.scene.triangles.push_back(t[0], t[1], t[2]);
    c.scene.material_id.push_back(0);
    const bool normals = i % 2 == 0;
    c.scene.attrib_flags.push_back(normals ? kHasNormals : 0);
    for (int k = 0; k < 3; ++k) c.scene.normals.push_back(normals ? unit(rng) : glm::vec3(0.0f));
    if (normals && i % 10 == 0) {  // opposite at two corners: they cancel halfway between
      c.scene.normals[3 * static_cast<std::size_t>(i) + 1] = -c.scene.normals[3 * static_cast<std::size_t>(i)];
    }
    Hit hit;
    hit.prim = static_cast<std::uint32_t>(i);
    hit.t = 1.0f;
    hit.u = rng.uniform();
    hit.v = rng.uniform() * (1.0f - hit.u);
    if (normals && i % 10 == 0) hit.u = 0.5f, hit.v = 0.0f;
    if (i % 13 == 5) hit.instance = 0;  // drawn through an instance: make_surface_point's
    if (i % 17 == 3) hit.prim = kNoHit;
    Ray ray;
    ray.dir = unit(rng) * std::pow(10.0f, 2.0f * rng.uniform() - 1.0f);  // any length, either side
    ray.org = centre - ray.dir;
    c.rays.push_back(ray);
    c.hits.push_back(hit);
  }
  // Rays along the surface: the wall 2x - y = 0 and directions in its plane, whose dot
  // with the normal is exactly 0 (2 / len and 1 / len differ by exactly a factor 2), the
  // side make_surface_point calls the front.
  for (int j = 0; j < 8; ++j) {
    const std::size_t i = c.scene.triangles.size();
    c.scene.triangles.push_back(glm::vec3(0.0f), glm::vec3(1.0f, 2.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f));
    c.scene.material_id.push_back(0);
    c.scene.attrib_flags.push_back(j % 2 ? kHasNormals : 0);
    for (int k = 0; k < 3; ++k) c.scene.normals.push_back(j % 2 ? unit(rng) : glm::vec3(0.0f));
    Hit hit;
    hit.prim = static_cast<std::uint32_t>(i);
    hit.t = 1.0f;
    hit.u = 0.25f;
    hit.v = 0.5f;
    Ray ray;
    ray.dir = j < 4 ? glm::vec3(1.0f, 2.0f, 0.5f * float(j + 1)) : glm::vec3(-1.0f, -2.0f, -0.25f * float(j));
    ray.org = glm::vec3(0.25f, 0.5f, 0.5f) - ray.dir;
    c.rays.push_back(ray);
    c.hits.push_back(hit);
  }
  return c;
}

TEST_P(SurfaceBatch, GivesMakeSurfacePointsGeometryBitForBit) {
  const Case c = make_case(0x5eed + static_cast<std::uint64_t>(GetParam()), 3000);
  const int n = static_cast<int>(c.hits.size());
  std::vector<SurfaceGeometry> geometry(c.hits.size());
  const int left = surface_geometry(c.scene, c.rays.data(), c.hits.data(), n, geometry.data(), GetParam());
  int computed = 0, mismatches = 0, left_counted = 0;
  for (int i = 0; i < n; ++i) {
    const Hit& hit = c.hits[static_cast<std::size_t>(i)];
    const SurfaceGeometry& g = geometry[static_cast<std::size_t>(i)];
    if (!hit.valid() || hit.instance != kNoHit) {
      EXPECT_FALSE(g.valid) << i;
      if (hit.valid()) ++left_counted;
      continue;
    }
    if (!g.valid) {
      ++left_counted;
      continue;
    }
    ++computed;
    const SurfacePoint want = make_surface_point(c.scene, c.rays[static_cast<std::size_t>(i)], hit, nullptr);
    if ((!same(g.p, want.p) || !same(g.ng, want.ng) || !same(g.ns, want.ns) || g.front_face != want.front_face) &&
        ++mismatches <= 5)
      ADD_FAILURE() << "hit " << i << ": batch p (" << g.p.x << ", " << g.p.y << ", " << g.p.z << ") ns ("
                    << g.ns.x << ", " << g.ns.y << ", " << g.ns.z << "), make_surface_point p (" << want.p.x << ", "
                    << want.p.y << ", " << want.p.z << ") ns (" << want.ns.x << ", " << want.ns.y << ", " << want.ns.z
                    << ")";
    // Through the geometry, make_surface_point returns the same point as without it.
    const SurfacePoint via = make_surface_point(c.scene, c.rays[static_cast<std::size_t>(i)], hit, nullptr, &g);
    EXPECT_TRUE(same(via.p, want.p) && same(via.ng, want.ng) && same(via.ns, want.ns) && via.material == want.material)
        << i;
  }
  EXPECT_EQ(mismatches, 0) << "of " << computed << " hits";
  EXPECT_EQ(left, left_counted);
  if (GetParam() == Isa::Scalar) {
    EXPECT_EQ(computed, 0) << "the scalar ISA leaves every hit to make_surface_point";
  } else {
    EXPECT_GT(computed, 2400) << "most hits take the vector path";
    // The triangles without a usable normal length are left (1 in 50), and still valid
    // through make_surface_point's fallback.
    EXPECT_FALSE(geometry[7].valid);
    // The rays along the wall are computed, and called front faces as make_surface_point does.
    for (int i = n - 8; i < n; ++i) {
      EXPECT_TRUE(geometry[static_cast<std::size_t>(i)].valid) << i;
      EXPECT_TRUE(geometry[static_cast<std::size_t>(i)].front_face) << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, SurfaceBatch, ::testing::Values(Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512),
                         [](const ::testing::TestParamInfo<Isa>& p) { return std::string(isa_name(p.param)); });

}  // namespace
}  // namespace lancer
