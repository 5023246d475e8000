// A scene whose meshes are drawn through instances (--instancing on) against the same file
// copied into world space (off): the same hits, shading points and image within noise, and
// no ray leaving an instanced surface hits it again, however the instance moves it.
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "caustic_test_support.h"
#include "render/camera.h"
#include "render/drawn_triangle.h"
#include "render/lights.h"
#include "render/renderer.h"
#include "render/shading_inputs.h"
#include "render/surface.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

int add_material(GltfBuilder& b, glm::vec3 color, glm::vec3 emission = glm::vec3(0.0f), bool double_sided = false) {
  return b.push("materials", {{"pbrMetallicRoughness",
                               {{"baseColorFactor", {color.x, color.y, color.z, 1.0}}, {"metallicFactor", 0.0}}},
                              {"emissiveFactor", {emission.x, emission.y, emission.z}},
                              {"doubleSided", double_sided}});
}

// A tent with smooth normals and tangents, a floor drawn once, and a small one-sided
// emitter facing down; the tent is drawn five times (turned, squashed, mirrored), the
// emitter twice (once mirrored, so its front side is the other one of its stored triangles).
GltfBuilder instanced_room() {
  GltfBuilder b;
  const int grey = add_material(b, glm::vec3(0.6f));
  const int tinted = add_material(b, glm::vec3(0.7f, 0.4f, 0.2f));
  const int light = add_material(b, glm::vec3(0.0f), glm::vec3(6.0f, 5.0f, 4.0f));

  const std::vector<glm::vec3> p = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 1.2f, 0}};
  std::vector<glm::vec3> n;
  for (const glm::vec3& v : p) n.push_back(glm::normalize(v + glm::vec3(0.0f, 1.5f, 0.0f)));
  const std::vector<glm::vec4> t = {{1, 0, 0, 1}, {1, 0, 0, 1}, {0, 0, 1, -1}, {0, 1, 1, 1}, {1, 1, 0, -1}};
  const std::vector<std::uint16_t> tent_indices = {0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0};
  const int tent = b.add_mesh({{"POSITION", b.add_vec3(p)}, {"NORMAL", b.add_vec3(n)}, {"TANGENT", b.add_vec4(t)}}, 4,
                              b.add_indices(tent_indices), tinted);
  const std::vector<std::uint16_t> quad = {0, 1, 2, 0, 2, 3};
  const int floor = b.add_mesh(
      {{"POSITION", b.add_vec3(std::vector<glm::vec3>{{-8, 0, -8}, {-8, 0, 8}, {8, 0, 8}, {8, 0, -8}})}}, 4,
      b.add_indices(quad), grey);
  // Faces down (-y): its corners run clockwise seen from above.
  const int lamp = b.add_mesh(
      {{"POSITION", b.add_vec3(std::vector<glm::vec3>{{-0.6f, 0, -0.6f}, {0.6f, 0, -0.6f}, {0.6f, 0, 0.6f}, {-0.6f, 0, 0.6f}})}},
      4, b.add_indices(quad), light);

  std::vector<int> roots = {b.add_node({{"mesh", floor}})};
  roots.push_back(b.add_node({{"mesh", tent}, {"translation", {-2.0, 0.0, 0.0}}}));
  roots.push_back(b.add_node({{"mesh", tent},
                              {"translation", {1.5, 0.0, -1.0}},
                              {"rotation", {0.0, std::sin(0.4), 0.0, std::cos(0.4)}},
                              {"scale", {0.8, 1.6, 0.5}}}));
  roots.push_back(b.add_node({{"mesh", tent}, {"translation", {0.0, 0.0, 2.0}}, {"scale", {-1.2, 0.7, 1.0}}}));
  roots.push_back(b.add_node({{"mesh", tent},
                              {"translation", {3.0, 2.5, 2.0}},
                              {"rotation", {std::sin(0.6), 0.0, 0.0, std::cos(0.6)}},
                              {"scale", {0.5, 0.5, 0.5}}}));
  roots.push_back(b.add_node({{"mesh", tent}, {"translation", {-3.0, 0.0, 3.0}}, {"scale", {1.0, 1.0, -1.0}}}));
  roots.push_back(b.add_node({{"mesh", lamp}, {"translation", {-1.0, 4.0, 0.0}}}));
  // Mirrored by y -> -y and turned over by a half turn about x: it faces down again.
  roots.push_back(b.add_node({{"mesh", lamp},
                              {"translation", {1.5, 4.0, 1.0}},
                              {"rotation", {1.0, 0.0, 0.0, 0.0}},
                              {"scale", {1.0, -1.0, 1.0}}}));
  b.set_scene(roots);
  return b;
}

PinholeCamera room_camera(int size) {
  return PinholeCamera::look_at({0.5f, 5.0f, 9.0f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 0.8f, size, size);
}

class InstancedRender : public gltf_test::GltfTempDir {
 protected:
  void SetUp() override {
    GltfTempDir::SetUp();
    instanced_room().write_data_uri_gltf(path("room.gltf"));
    flat_ = read_gltf(path("room.gltf"), -1, std::nullopt, InstancingMode::Off);
    shared_ = read_gltf(path("room.gltf"), -1, std::nullopt, InstancingMode::On);
  }
  Scene flat_, shared_;
};

TEST_F(InstancedRender, SceneIsDrawnThroughInstances) {
  ASSERT_TRUE(flat_.instancing.empty());
  ASSERT_EQ(shared_.instancing.meshes.size(), 3u);      // the floor in world space, tent, lamp
  ASSERT_EQ(shared_.instancing.instances.size(), 8u);  // identity, five tents, two lamps
  EXPECT_EQ(shared_.drawn_triangle_count(), flat_.triangle_count());
}

// Every pixel's camera ray: the same triangle of the file (by source id) at the same
// distance, and the same shading point, normals and tangent frame.
TEST_F(InstancedRender, HitsAndShadingPointsMatchTheFlattenedCopy) {
  const std::unique_ptr<Accelerator> flat_accel = make_accelerator("kdtree", flat_.triangles);
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", shared_.triangles, shared_.instancing);
  const int size = 96;
  const PinholeCamera camera = room_camera(size);
  int both = 0, disagree = 0, instanced_hits = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Ray ray = camera.generate(float(x) + 0.5f, float(y) + 0.5f);
      const Hit a = flat_accel->intersect(ray), b = accel->intersect(ray);
      if (!a.valid() && !b.valid()) continue;
      if (a.valid() != b.valid() || flat_.source_triangle_id[a.prim] != shared_.source_id(b.prim, b.instance)) {
        ++disagree;  // allowed only on an edge between two triangles (counted below)
        continue;
      }
      ++both;
      instanced_hits += shared_.instance_transform(b.instance) != nullptr;
      EXPECT_NEAR(b.t, a.t, 1e-5f * a.t) << x << "," << y;
      const ShadingInputs sa = evaluate_shading(flat_, ray, a), sb = evaluate_shading(shared_, ray, b);
      EXPECT_LT(glm::length(sa.p - sb.p), 1e-4f) << x << "," << y;
      EXPECT_LT(glm::length(sa.ng - sb.ng), 1e-4f) << x << "," << y;
      EXPECT_LT(glm::length(sa.ns - sb.ns), 1e-4f) << x << "," << y;
      EXPECT_LT(glm::length(sa.tangent - sb.tangent), 1e-3f) << x << "," << y;
      EXPECT_EQ(sa.front_face, sb.front_face) << x << "," << y;
      EXPECT_EQ(sa.emission, sb.emission) << x << "," << y;
      EXPECT_EQ(sa.base_color, sb.base_color) << x << "," << y;
    }
  EXPECT_GT(both, size * size / 2);
  EXPECT_GT(instanced_hits, size * size / 10);
  EXPECT_LE(disagree, size * size / 500) << "rays that found another triangle in the instanced scene";
}

TEST_F(InstancedRender, EachDrawnEmitterIsALightWithItsFlattenedCopysFrontSide) {
  const AreaLights flat(flat_), shared(shared_);
  ASSERT_EQ(shared.size(), flat.size());
  ASSERT_EQ(shared.size(), 4u);  // two triangles per lamp
  for (std::size_t i = 0; i < shared.size(); ++i) {
    const EmissiveTriangle& s = shared.light(i);
    EXPECT_NE(shared_.instance_transform(s.instance), nullptr);
    EXPECT_NEAR(s.normal.y, -1.0f, 1e-6f) << "light " << i << " must face down, as its flattened copy does";
    EXPECT_FLOAT_EQ(shared.pdf_area(s.prim, s.instance), shared.pick_probability(i) / s.area);
    EXPECT_EQ(shared.pdf_area(s.prim, kNoHit), 0.0f);
    EXPECT_NEAR(s.area, flat.light(i).area, 1e-5f);
    EXPECT_NEAR(shared.pick_probability(i), flat.pick_probability(i), 1e-6f);
  }
}

// The path tracer's image of both, over independent seeds: every block within noise.
TEST_F(InstancedRender, PathTracedImageMatchesTheFlattenedCopyWithinNoise) {
  const std::unique_ptr<Accelerator> flat_accel = make_accelerator("kdtree", flat_.triangles);
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", shared_.triangles, shared_.instancing);
  const PinholeCamera camera = room_camera(32);
  auto render = [&](const Scene& scene, const Accelerator& a) {
    return [&](std::uint64_t seed) {
      RenderSettings s;
      s.width = s.height = 32;
      s.spp = 32;
      s.max_depth = 4;
      s.threads = 2;
      s.seed = seed;
      RenderStats stats;
      return render_image(scene, a, camera, s, stats);
    };
  };
  const test::SeedStats flat = test::over_seeds(6, render(flat_, *flat_accel));
  const test::SeedStats shared = test::over_seeds(6, render(shared_, *accel));
  const int resolved = test::expect_same_block_means(flat, shared, "instanced", 0.1);
  EXPECT_GE(resolved, 8) << "too few blocks resolve a 10% difference";
}

// Rays leaving points of instanced triangles, in every direction, never report the triangle
// they leave (the same triangle through the same instance) whatever the instance's scale,
// offset or turn: the offsets follow the rays into the instance's space (ray_offset.h).
TEST(InstancedOffsets, RaysLeavingAnInstancedSurfaceNeverHitItAgain) {
  Scene scene;
  // A bumpy strip of triangles, stored once.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 40; ++i) {
    const float x = float(i % 8), z = float(i / 8);
    scene.triangles.push_back({x, u(rng) * 0.3f, z}, {x + 1.0f, u(rng) * 0.3f, z}, {x, u(rng) * 0.3f, z + 1.0f});
    scene.material_id.push_back(0);
    scene.source_triangle_id.push_back(std::uint32_t(i));
  }
  scene.attrib_flags.assign(scene.triangle_count(), 0);
  scene.materials.emplace_back();
  scene.instancing.meshes.push_back({0, std::uint32_t(scene.triangle_count())});
  struct Placement {
    glm::vec3 scale, offset;
    float angle;
  };
  const Placement placements[] = {{{1, 1, 1}, {0, 0, 0}, 0.0f},        {{1e3f, 1e3f, 1e3f}, {5e4f, -3e4f, 1e4f}, 0.7f},
                                  {{1e-3f, 2e-3f, 1e-3f}, {1e3f, 2e3f, -1e3f}, 2.1f}, {{-3, 0.5f, 7}, {0.1f, 0.2f, 0.3f}, 4.0f},
                                  {{1, 1, 1}, {1e6f, 0, 0}, 1.0f}};
  for (const Placement& pl : placements) {
    const float c = std::cos(pl.angle), s = std::sin(pl.angle);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(c * pl.scale.x, s * pl.scale.x, 0, 0);
    m[1] = glm::dvec4(-s * pl.scale.y, c * pl.scale.y, 0, 0);
    m[2] = glm::dvec4(0, 0, pl.scale.z, 0);
    m[3] = glm::dvec4(glm::dvec3(pl.offset), 1);
    const glm::dmat3 l(m), inv = glm::inverse(l);
    Instance inst;
    inst.to_world = Affine{glm::mat3(l), glm::vec3(pl.offset)};
    inst.to_object = Affine{glm::mat3(inv), glm::vec3(-(inv * glm::dvec3(pl.offset)))};
    scene.instancing.instances.push_back(inst);
  }
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", scene.triangles, scene.instancing);
  int rehits = 0, rays = 0;
  for (std::uint32_t k = 0; k < scene.instancing.instances.size(); ++k)
    for (std::uint32_t prim = 0; prim < scene.triangle_count(); ++prim)
      for (int sample = 0; sample < 40; ++sample) {
        float b1 = u(rng), b2 = u(rng);
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        const Hit hit{1.0f, prim, b1, b2, k};
        const TriangleCorners c = drawn_corners(scene, prim, scene.instance_transform(k));
        const glm::vec3 n = glm::normalize(drawn_front_normal(c, scene.instance_transform(k)));
        Ray probe;
        probe.org = c[0] + (c[1] - c[0]) * 0.3f + (c[2] - c[0]) * 0.3f + n;
        probe.dir = -n;
        const SurfacePoint sp = make_surface_point(scene, probe, hit);
        // Any direction, grazing ones included.
        glm::vec3 dir(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
        if (sample % 4 == 0) dir = glm::normalize(glm::cross(sp.ng, dir)) + sp.ng * (u(rng) - 0.5f) * 1e-3f;
        Ray r;
        r.org = leaving_offset(scene, sp.p, sp.ng, prim, k, 0.0f).origin(dir);
        r.dir = dir;
        const Hit again = accel->intersect(r);
        ++rays;
        rehits += again.valid() && again.prim == prim && again.instance == k;
      }
  EXPECT_EQ(rehits, 0) << "of " << rays << " rays";
}

}  // namespace
}  // namespace lancer
