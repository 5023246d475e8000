// Watertightness of the oracle on closed tessellated spheres: rays aimed exactly at the
// shared vertices and edges of a closed mesh never pass through it (Woop et al. 2013).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "accel/brute_force.h"
#include "scene/procedural.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

// Rays from splitmix64, the same on every platform.
struct Rng : SplitMix64 {
  using SplitMix64::SplitMix64;
  glm::vec3 in_ball(float r) {
    for (;;) {
      const glm::vec3 p(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
      if (p.x * p.x + p.y * p.y + p.z * p.z < 1.0f) return r * p;
    }
  }
};

// Every corner and every edge midpoint-ish point (corner + s * edge) of the mesh.
std::vector<glm::vec3> targets_on_vertices_and_edges(const TriangleSoA& t, Rng& rng) {
  std::vector<glm::vec3> out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 a = t.vertex(i, k), b = t.vertex(i, (k + 1) % 3);
      out.push_back(a);
      out.push_back(a + 0.5f * (b - a));
      out.push_back(a + rng.uniform() * (b - a));
    }
  }
  return out;
}

struct Escapes {
  int from_inside = 0;
  int from_outside = 0;
  int rays = 0;
};

Escapes shoot(const Scene& scene, glm::vec3 center, float radius, std::uint64_t seed) {
  const BruteForce oracle(scene.triangles);
  Rng rng(seed);
  Escapes e;
  for (const glm::vec3& target : targets_on_vertices_and_edges(scene.triangles, rng)) {
    // From inside: any ray from inside a closed surface must hit it.
    Ray in;
    in.org = center + rng.in_ball(0.5f * radius);
    in.dir = target - in.org;
    const Hit h = oracle.intersect(in);
    e.from_inside += (h.valid() && oracle.occluded(in)) ? 0 : 1;
    // From outside, through the target into the solid: it must hit before the far side.
    Ray out;
    out.org = center + 3.0f * (target - center) + rng.in_ball(0.5f * radius);
    out.dir = target - out.org;
    e.from_outside += oracle.intersect(out).valid() ? 0 : 1;
    e.rays += 2;
  }
  return e;
}

TEST(WatertightMesh, UvSphereHasNoCracks) {
  Scene scene;
  const glm::vec3 c(0.3f, -1.7f, 2.1f);
  append_uv_sphere(scene, c, 1.25f, 48, 24, 0);
  const Escapes e = shoot(scene, c, 1.25f, 7);
  EXPECT_GT(e.rays, 35000);
  EXPECT_EQ(e.from_inside, 0);
  EXPECT_EQ(e.from_outside, 0);
}

TEST(WatertightMesh, IcosphereHasNoCracks) {
  Scene scene;
  const glm::vec3 c(-1000.0f, 250.0f, 17.0f);  // far from the origin, where ulps are coarse
  append_icosphere(scene, c, 3.0f, 3, 0);
  const Escapes e = shoot(scene, c, 3.0f, 11);
  EXPECT_GT(e.rays, 20000);
  EXPECT_EQ(e.from_inside, 0);
  EXPECT_EQ(e.from_outside, 0);
}

}  // namespace
}  // namespace lancer
