// From a hit to the shading point: position, normals, side and material.
#include "render/surface.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render_test_scenes.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

using test::ray_from;

struct OneTriangle {
  Scene scene;
  OneTriangle(const glm::vec3* normals) {
    scene.materials.push_back(test::diffuse_material({0.2f, 0.4f, 0.6f}));
    const glm::vec3 p[3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};  // faces +z
    CornerAttributes attribs;
    attribs.normals = normals;
    SceneBuilder(scene, "tri").add_triangle(p, 0, 7, attribs);
  }
  SurfacePoint shade(const Ray& ray) const {
    const BruteForce accel(scene.triangles);
    const Hit hit = accel.intersect(ray);
    EXPECT_TRUE(hit.valid());
    return make_surface_point(scene, ray, hit);
  }
};

TEST(Surface, PositionAndGeometricNormalFromTheFront) {
  const OneTriangle t(nullptr);
  const SurfacePoint sp = t.shade(ray_from({0.5f, 0.25f, 3}, {0, 0, -1}));
  EXPECT_NEAR(sp.p.x, 0.5f, 1e-6f);
  EXPECT_NEAR(sp.p.y, 0.25f, 1e-6f);
  EXPECT_EQ(sp.p.z, 0.0f);
  EXPECT_EQ(sp.ng, glm::vec3(0, 0, 1));
  EXPECT_EQ(sp.ns, sp.ng);  // no normals in the file: the geometric normal
  EXPECT_TRUE(sp.front_face);
  EXPECT_EQ(sp.prim, 0u);
  EXPECT_EQ(sp.base_color, glm::vec3(0.2f, 0.4f, 0.6f));
  EXPECT_EQ(sp.material, &t.scene.materials[0]);
}

TEST(Surface, BackSideFlipsBothNormals) {
  const OneTriangle t(nullptr);
  const SurfacePoint sp = t.shade(ray_from({0.5f, 0.25f, -3}, glm::normalize(glm::vec3(0.1f, 0, 1))));
  EXPECT_FALSE(sp.front_face);
  EXPECT_EQ(sp.ng, glm::vec3(0, 0, -1));
  EXPECT_EQ(sp.ns, glm::vec3(0, 0, -1));
  EXPECT_EQ(sp.stored_shading_normal(), glm::vec3(0, 0, 1));
}

TEST(Surface, ShadingNormalIsInterpolatedFromTheCorners) {
  const glm::vec3 n[3] = {glm::normalize(glm::vec3(0, 0, 1)), glm::normalize(glm::vec3(1, 0, 1)),
                          glm::normalize(glm::vec3(0, 1, 2))};
  const OneTriangle t(n);
  ASSERT_TRUE(t.scene.attrib_flags[0] & kHasNormals);
  // (x, y) = (0.5, 0.25) on the triangle (0,0), (2,0), (0,2): u = 0.25, v = 0.125.
  const SurfacePoint sp = t.shade(ray_from({0.5f, 0.25f, 3}, {0, 0, -1}));
  const glm::vec3 want = glm::normalize(0.625f * n[0] + 0.25f * n[1] + 0.125f * n[2]);
  EXPECT_NEAR(sp.ns.x, want.x, 1e-6f);
  EXPECT_NEAR(sp.ns.y, want.y, 1e-6f);
  EXPECT_NEAR(sp.ns.z, want.z, 1e-6f);
  EXPECT_EQ(sp.ng, glm::vec3(0, 0, 1));
  // From behind, the shading normal flips with the geometric one.
  const SurfacePoint back = t.shade(ray_from({0.5f, 0.25f, -3}, {0, 0, 1}));
  EXPECT_NEAR(back.ns.x, -want.x, 1e-6f);
  EXPECT_NEAR(back.ns.z, -want.z, 1e-6f);
}

TEST(Surface, ZeroLengthNormalsFallBackToTheGeometricNormal) {
  const glm::vec3 n[3] = {glm::vec3(0), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)};
  const OneTriangle t(n);
  const SurfacePoint sp = t.shade(ray_from({0.5f, 0.25f, 3}, {0, 0, -1}));
  EXPECT_EQ(sp.ns, sp.ng);
}

TEST(Surface, SmoothSphereNormalsPointAwayFromTheCentre) {
  Scene scene;
  scene.materials.push_back(test::diffuse_material(glm::vec3(1.0f)));
  append_icosphere(scene, {1, 2, 3}, 2.0f, 3, 0);
  const BruteForce accel(scene.triangles);
  for (const glm::vec3 d : {glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, -2, 0.5f))}) {
    const Ray r = ray_from(glm::vec3(1, 2, 3) - 10.0f * d, d);
    const SurfacePoint sp = make_surface_point(scene, r, accel.intersect(r));
    const glm::vec3 radial = glm::normalize(sp.p - glm::vec3(1, 2, 3));
    EXPECT_GT(glm::dot(sp.ns, radial), 0.9999f);
    EXPECT_GT(glm::dot(sp.ng, radial), 0.99f);
    EXPECT_TRUE(sp.front_face);
  }
}

}  // namespace
}  // namespace lancer
