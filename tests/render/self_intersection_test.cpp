// Secondary and shadow rays leave from the surface point the renderer computes (from the
// barycentrics of the hit) with offset_ray_origin: even nearly tangent, they must never hit
// the triangle they start from.
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "accel/ray_offset.h"
#include "render/sampler.h"
#include "render/surface.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

// A unit direction at `elevation` radians above the tangent plane of unit normal n
// (below it when elevation < 0), at azimuth phi.
glm::vec3 near_tangent(const glm::vec3& n, float elevation, float phi) {
  const glm::vec3 helper = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 t = glm::normalize(glm::cross(n, helper));
  const glm::vec3 b = glm::cross(n, t);
  const glm::vec3 tangent = std::cos(phi) * t + std::sin(phi) * b;
  return glm::normalize(std::cos(elevation) * tangent + std::sin(elevation) * n);
}

// The hit of a ray aimed at barycentrics (u, v) of triangle `prim` from `eye`.
SurfacePoint hit_point(const Scene& scene, const BruteForce& accel, std::uint32_t prim, float u, float v,
                       const glm::vec3& eye) {
  const glm::vec3 a = scene.triangles.vertex(prim, 0), b = scene.triangles.vertex(prim, 1),
                  c = scene.triangles.vertex(prim, 2);
  const glm::vec3 target = (1.0f - u - v) * a + u * b + v * c;
  const Ray ray = test::ray_from(eye, glm::normalize(target - eye));
  const Hit hit = accel.intersect(ray);
  EXPECT_TRUE(hit.valid());
  return make_surface_point(scene, ray, hit);
}

TEST(SelfIntersection, LargeTiltedTriangleAtGrazingAngles) {
  Scene scene;
  scene.materials.push_back(test::diffuse_material(glm::vec3(0.5f)));
  // Far from the origin and tilted on every axis, so the offset works with large ulps.
  const glm::vec3 p[3] = {{1000.0f, 480.0f, -300.0f}, {1700.0f, 520.0f, -150.0f}, {1150.0f, 900.0f, 200.0f}};
  SceneBuilder(scene, "tilted").add_triangle(p, 0, 0);
  const BruteForce accel(scene.triangles);
  const glm::vec3 centroid = (p[0] + p[1] + p[2]) / 3.0f;
  const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));

  int rays = 0, self_hits = 0;
  for (std::uint32_t i = 0; i < 2000; ++i) {
    const PixelSampler s(i, 0, 0, 11);
    float u = s.get(0), v = s.get(1);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    // Seen from both sides.
    const glm::vec3 eye = centroid + (i % 2 ? 800.0f : -800.0f) * n + 300.0f * (s.get(2) - 0.5f) * glm::vec3(1, 1, 0);
    const SurfacePoint sp = hit_point(scene, accel, 0, u, v, eye);
    for (float elevation : {1e-2f, 1e-3f, 1e-4f, -1e-2f, -1e-3f, -1e-4f}) {
      const glm::vec3 dir = near_tangent(sp.ng, elevation, 6.2831853f * s.get(3));
      // As the integrator does: offset towards the side the ray leaves.
      Ray r = test::ray_from(offset_ray_origin(sp.p, elevation > 0 ? sp.ng : -sp.ng), dir);
      ++rays;
      self_hits += accel.occluded(r);
    }
  }
  EXPECT_EQ(self_hits, 0) << "of " << rays << " rays";
}

TEST(SelfIntersection, WithoutTheOffsetSelfHitsHappen) {
  // The same set-up without offsetting shows the test can fail.
  Scene scene;
  scene.materials.push_back(test::diffuse_material(glm::vec3(0.5f)));
  const glm::vec3 p[3] = {{1000.0f, 480.0f, -300.0f}, {1700.0f, 520.0f, -150.0f}, {1150.0f, 900.0f, 200.0f}};
  SceneBuilder(scene, "tilted").add_triangle(p, 0, 0);
  const BruteForce accel(scene.triangles);
  const glm::vec3 centroid = (p[0] + p[1] + p[2]) / 3.0f;
  const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
  int self_hits = 0;
  for (std::uint32_t i = 0; i < 500; ++i) {
    const PixelSampler s(i, 0, 0, 11);
    float u = s.get(0), v = s.get(1);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const SurfacePoint sp = hit_point(scene, accel, 0, u, v, centroid + 800.0f * n);
    const Ray r = test::ray_from(sp.p, near_tangent(sp.ng, 1e-3f, 6.2831853f * s.get(3)));
    self_hits += accel.occluded(r);
  }
  EXPECT_GT(self_hits, 0);
}

TEST(SelfIntersection, TessellatedSphereOutwardAndInward) {
  Scene scene;
  scene.materials.push_back(test::diffuse_material(glm::vec3(0.5f)));
  const glm::vec3 centre(3.0f, -2.0f, 40.0f);
  const float radius = 1.5f;
  append_uv_sphere(scene, centre, radius, 48, 24, 0);
  const BruteForce accel(scene.triangles);

  int outward_hits = 0, inward_self = 0, inward_miss = 0, total = 0;
  for (std::uint32_t i = 0; i < 600; ++i) {
    const PixelSampler s(i, 1, 0, 12);
    // A random point on the sphere seen from outside, along its direction from the centre.
    const float z = 2.0f * s.get(0) - 1.0f, phi = 6.2831853f * s.get(1);
    const float rxy = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const glm::vec3 dir_out(rxy * std::cos(phi), rxy * std::sin(phi), z);
    const Ray camera = test::ray_from(centre + 5.0f * radius * dir_out, -dir_out);
    const Hit hit = accel.intersect(camera);
    ASSERT_TRUE(hit.valid());
    const SurfacePoint sp = make_surface_point(scene, camera, hit);
    for (float elevation : {1e-2f, 1e-3f, 1e-4f}) {
      ++total;
      // Outward, just above the facet's plane: on a convex mesh nothing can be hit.
      const glm::vec3 up = near_tangent(sp.ng, elevation, 6.2831853f * s.get(2));
      outward_hits += accel.occluded(test::ray_from(offset_ray_origin(sp.p, sp.ng), up));
      // Inward (a refracted ray): must hit another triangle of the sphere, never its own.
      const glm::vec3 down = near_tangent(sp.ng, -elevation, 6.2831853f * s.get(3));
      const Hit in = accel.intersect(test::ray_from(offset_ray_origin(sp.p, -sp.ng), down));
      inward_self += in.valid() && in.prim == sp.prim;
      inward_miss += !in.valid();
    }
  }
  EXPECT_EQ(outward_hits, 0) << "of " << total;
  EXPECT_EQ(inward_self, 0) << "of " << total;
  EXPECT_EQ(inward_miss, 0) << "of " << total;
}

}  // namespace
}  // namespace lancer
