// The standard ray sets: tile order, camera rays at pixel centres, diffuse bounces that
// leave the surface into the normal's hemisphere with a cosine distribution, shadow rays
// that stop short of the light, and determinism.
#include "render/ray_sets.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/task_arena.h>

#include "accel/accel_factory.h"
#include "accel/brute_force.h"
#include "render_test_scenes.h"
#include "scene/load_scene.h"
#include "simd/splitmix64.h"
#include "test_paths.h"

namespace lancer {
namespace {

bool same_bits(const Ray& a, const Ray& b) {
  auto eq = [](float x, float y) { return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); };
  return eq(a.org.x, b.org.x) && eq(a.org.y, b.org.y) && eq(a.org.z, b.org.z) && eq(a.tnear, b.tnear) &&
         eq(a.dir.x, b.dir.x) && eq(a.dir.y, b.dir.y) && eq(a.dir.z, b.dir.z) && eq(a.tfar, b.tfar);
}

bool same_bits(const std::vector<Ray>& a, const std::vector<Ray>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_bits(a[i], b[i])) return false;
  return true;
}

Scene cornell() { return load_scene(test::scenes_dir() / "cornell-box.gltf"); }

PinholeCamera cornell_camera(const Scene& scene, int size) {
  EXPECT_FALSE(scene.cameras.empty());
  return PinholeCamera::from_desc(scene.cameras.at(0), size, size);
}

// The unit geometric normal of triangle `prim`, flipped to face against `dir`.
glm::dvec3 facing_normal(const Scene& scene, std::uint32_t prim, const glm::vec3& dir) {
  const glm::dvec3 a(scene.triangles.vertex(prim, 0)), b(scene.triangles.vertex(prim, 1)),
      c(scene.triangles.vertex(prim, 2));
  glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  return glm::dot(n, glm::dvec3(dir)) > 0.0 ? -n : n;
}

// Signed distance of p from the plane of triangle `prim` along `n`.
double plane_distance(const Scene& scene, std::uint32_t prim, const glm::dvec3& n, const glm::vec3& p) {
  return glm::dot(glm::dvec3(p) - glm::dvec3(scene.triangles.vertex(prim, 0)), n);
}

// The primary hits of the camera rays, in their order, from the oracle.
std::vector<Hit> oracle_primary_hits(const Scene& scene, const PinholeCamera& camera) {
  const BruteForce brute(scene.triangles);
  std::vector<Hit> hits;
  for (const Ray& r : primary_rays(camera)) hits.push_back(brute.intersect(r));
  return hits;
}

TEST(RaySets, NamesParseBack) {
  for (RaySet s : {RaySet::Primary, RaySet::Diffuse, RaySet::Shadow}) EXPECT_EQ(parse_ray_set(ray_set_name(s)), s);
  EXPECT_FALSE(parse_ray_set("ambient"));
}

TEST(RaySets, TileOrderVisitsTilesInRowOrderAndEachTileRowMajor) {
  EXPECT_EQ(tile_order_pixel(0, 16), std::make_pair(0, 0));
  EXPECT_EQ(tile_order_pixel(7, 16), std::make_pair(7, 0));
  EXPECT_EQ(tile_order_pixel(8, 16), std::make_pair(0, 1));
  EXPECT_EQ(tile_order_pixel(63, 16), std::make_pair(7, 7));
  EXPECT_EQ(tile_order_pixel(64, 16), std::make_pair(8, 0));
  EXPECT_EQ(tile_order_pixel(127, 16), std::make_pair(15, 7));
  EXPECT_EQ(tile_order_pixel(128, 16), std::make_pair(0, 8));
  // Every pixel of a 24x16 image exactly once.
  std::set<std::pair<int, int>> seen;
  for (std::size_t i = 0; i < 24 * 16; ++i) {
    const auto p = tile_order_pixel(i, 24);
    EXPECT_TRUE(p.first >= 0 && p.first < 24 && p.second >= 0 && p.second < 16) << i;
    seen.insert(p);
  }
  EXPECT_EQ(seen.size(), 24u * 16u);
}

TEST(RaySets, PrimaryRaysAreCameraRaysThroughPixelCentresInTileOrder) {
  const int w = 32, h = 16;
  const PinholeCamera camera =
      PinholeCamera::look_at(glm::vec3(1, 2, 3), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0), 0.9f, w, h);
  const std::vector<Ray> rays = primary_rays(camera);
  ASSERT_EQ(rays.size(), static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t tile = static_cast<std::size_t>((y / 8) * (w / 8) + x / 8);
      const std::size_t index = tile * 64 + static_cast<std::size_t>((y % 8) * 8 + x % 8);
      const Ray expected = camera.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
      EXPECT_TRUE(same_bits(rays[index], expected)) << "pixel " << x << "," << y;
    }
  }
}

TEST(RaySets, ImageSidesMustBeMultiplesOf8) {
  for (auto [w, h] : {std::pair{20, 16}, std::pair{16, 12}, std::pair{4, 8}}) {
    const PinholeCamera camera =
        PinholeCamera::look_at(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0), 0.9f, w, h);
    EXPECT_THROW(primary_rays(camera), std::invalid_argument) << w << "x" << h;
  }
}

TEST(RaySets, CosineHemisphereDirectionsAreUnitInsideTheHemisphereAndCosineDistributed) {
  const glm::vec3 normals[] = {{0, 0, 1},   {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, glm::normalize(glm::vec3(1, 2, 3)),
                               glm::normalize(glm::vec3(-1e-3f, 1, 0)), glm::normalize(glm::vec3(0.3f, -0.2f, -0.9f))};
  for (const glm::vec3& n : normals) {
    SplitMix64 rng(11);
    constexpr int kSamples = 200000;
    double sum_cos = 0.0, sum_cos2 = 0.0;
    glm::dvec3 sum_tangential(0.0);
    for (int i = 0; i < kSamples; ++i) {
      const float u1 = rng.uniform();
      const float u2 = rng.uniform();
      const glm::vec3 d = cosine_hemisphere_direction(n, u1, u2);
      const float c = glm::dot(d, n);
      ASSERT_GT(c, 0.0f) << "u " << u1 << " " << u2;
      ASSERT_NEAR(glm::length(d), 1.0f, 1e-6f);
      sum_cos += c;
      sum_cos2 += static_cast<double>(c) * c;
      sum_tangential += glm::dvec3(d - c * n);
    }
    // Cosine-weighted: E[cos] = 2/3, E[cos^2] = 1/2, no preferred azimuth. Standard errors
    // are below 0.001 here, so these bounds are more than 5 sigma.
    EXPECT_NEAR(sum_cos / kSamples, 2.0 / 3.0, 0.005);
    EXPECT_NEAR(sum_cos2 / kSamples, 0.5, 0.005);
    EXPECT_LT(glm::length(sum_tangential / static_cast<double>(kSamples)), 0.01);
    // The extreme uniforms (sampler.h gives at most 1 - 2^-24) stay off the tangent plane.
    for (float u1 : {0.0f, 1.0f - 0x1p-24f})
      for (float u2 : {0.0f, 0.25f, 0.5f, 1.0f - 0x1p-24f}) EXPECT_GT(glm::dot(cosine_hemisphere_direction(n, u1, u2), n), 0.0f);
  }
}

TEST(RaySets, DiffuseRaysLeaveEachPrimaryHitIntoTheNormalsHemisphere) {
  const Scene scene = cornell();
  const PinholeCamera camera = cornell_camera(scene, 64);
  const BruteForce brute(scene.triangles);
  const std::vector<Ray> primary = primary_rays(camera);
  const std::vector<Hit> hits = oracle_primary_hits(scene, camera);
  const std::vector<Ray> diffuse = make_ray_set(scene, brute, camera, RaySet::Diffuse, 1);

  std::size_t k = 0, escaped_own_triangle = 0;
  double sum_cos = 0.0;
  for (std::size_t i = 0; i < primary.size(); ++i) {
    if (!hits[i].valid()) continue;
    ASSERT_LT(k, diffuse.size());
    const Ray& d = diffuse[k++];
    const glm::dvec3 n = facing_normal(scene, hits[i].prim, primary[i].dir);
    EXPECT_GT(plane_distance(scene, hits[i].prim, n, d.org), 0.0) << "ray " << k - 1 << " starts below the surface";
    const double c = glm::dot(glm::dvec3(d.dir), n);
    EXPECT_GT(c, 0.0) << "ray " << k - 1;
    EXPECT_NEAR(glm::length(d.dir), 1.0f, 1e-6f);
    EXPECT_EQ(d.tnear, 0.0f);
    EXPECT_EQ(d.tfar, kInfinity);
    // Near the hit point, along the camera ray.
    const glm::vec3 p = primary[i].org + hits[i].t * primary[i].dir;
    EXPECT_LT(glm::length(d.org - p), 1e-4f * (1.0f + glm::length(p)));
    // Leaving a flat triangle into its front hemisphere, a ray can never hit it again.
    escaped_own_triangle += brute.intersect(d).prim != hits[i].prim ? 1 : 0;
    sum_cos += c;
  }
  EXPECT_EQ(k, diffuse.size());
  EXPECT_GT(k, primary.size() / 2);  // the box fills most of the view
  EXPECT_EQ(escaped_own_triangle, k);
  EXPECT_NEAR(sum_cos / static_cast<double>(k), 2.0 / 3.0, 0.03);  // a few thousand samples
}

TEST(RaySets, ShadowRaysStopJustShortOfAPointOnTheLight) {
  const Scene scene = cornell();
  const PinholeCamera camera = cornell_camera(scene, 64);
  const BruteForce brute(scene.triangles);
  const std::vector<Ray> primary = primary_rays(camera);
  const std::vector<Hit> hits = oracle_primary_hits(scene, camera);
  const std::vector<Ray> shadow = make_ray_set(scene, brute, camera, RaySet::Shadow, 5);

  std::vector<std::uint32_t> emissive;
  for (std::uint32_t t = 0; t < scene.triangle_count(); ++t)
    if (scene.materials[scene.material_id[t]].emissive()) emissive.push_back(t);
  ASSERT_FALSE(emissive.empty());

  std::size_t k = 0, lit = 0;
  for (std::size_t i = 0; i < primary.size(); ++i) {
    if (!hits[i].valid()) continue;
    ASSERT_LT(k, shadow.size());
    const Ray& s = shadow[k++];
    const glm::dvec3 n = facing_normal(scene, hits[i].prim, primary[i].dir);
    EXPECT_GT(plane_distance(scene, hits[i].prim, n, s.org), 0.0) << "ray " << k - 1 << " starts below the surface";
    EXPECT_LT(s.tfar, 1.0f);
    EXPECT_GT(s.tfar, 0.999f);
    // At t = 1 the ray reaches a point on one of the light's triangles (lifted off by a few ulps).
    const glm::vec3 target = s.org + s.dir;
    bool on_light = false;
    for (std::uint32_t t : emissive) {
      const glm::vec3 a = scene.triangles.vertex(t, 0), e1 = scene.triangles.vertex(t, 1) - a,
                      e2 = scene.triangles.vertex(t, 2) - a;
      const glm::vec3 ln = glm::normalize(glm::cross(e1, e2));
      if (std::abs(glm::dot(target - a, ln)) > 1e-4f) continue;
      // Barycentrics of the target in the light's plane.
      const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
      const float p1 = glm::dot(target - a, e1), p2 = glm::dot(target - a, e2);
      const float det = d11 * d22 - d12 * d12;
      const float u = (d22 * p1 - d12 * p2) / det, v = (d11 * p2 - d12 * p1) / det;
      on_light = on_light || (u > -1e-4f && v > -1e-4f && u + v < 1.0f + 1e-4f);
    }
    EXPECT_TRUE(on_light) << "ray " << k - 1 << " does not aim at the light";
    // The light never occludes a shadow ray from its front side: the ray stops short of it.
    // (From behind the light, e.g. from the ceiling above it, the light's back does occlude.)
    Ray unbounded = s;
    unbounded.tfar = kInfinity;
    const Hit h = brute.intersect(unbounded);
    if (h.valid() && scene.materials[scene.material_id[h.prim]].emissive() && h.t < s.tfar) {
      const glm::dvec3 a(scene.triangles.vertex(h.prim, 0)), b(scene.triangles.vertex(h.prim, 1)),
          c(scene.triangles.vertex(h.prim, 2));
      EXPECT_LE(glm::dot(glm::dvec3(s.org) - a, glm::cross(b - a, c - a)), 0.0)
          << "ray " << k - 1 << " from the light's front side hits the light at t " << h.t;
    }
    lit += brute.occluded(s) ? 0 : 1;
  }
  EXPECT_EQ(k, shadow.size());
  EXPECT_GT(lit, shadow.size() / 3);  // most of the box sees the ceiling light
}

// A floor square facing +z under a camera looking down, with the lights given.
Scene floor_scene() {
  Scene scene;
  scene.source = "floor";
  const std::uint32_t grey = test::add_material(scene, test::diffuse_material(glm::vec3(0.5f)));
  test::add_square_z(scene, 0, 0, 0, 2, true, grey);
  return scene;
}

PinholeCamera floor_camera() {
  return PinholeCamera::look_at(glm::vec3(0, 0, 5), glm::vec3(0), glm::vec3(0, 1, 0), 0.5f, 16, 16);
}

TEST(RaySets, ShadowRaysGoToTheFirstPunctualLightWithoutEmissiveTriangles) {
  Scene scene = floor_scene();
  PunctualLight point;
  point.position = glm::vec3(0.5f, -0.25f, 3.0f);
  PunctualLight sun;
  sun.type = LightType::Directional;
  sun.direction = glm::vec3(0, 1, -2);
  scene.lights = {point, sun};
  const BruteForce brute(scene.triangles);
  const std::vector<Ray> shadow = make_ray_set(scene, brute, floor_camera(), RaySet::Shadow, 0);
  ASSERT_EQ(shadow.size(), 256u);  // the floor fills the view
  for (const Ray& s : shadow) {
    EXPECT_GT(s.org.z, 0.0f);
    EXPECT_EQ(s.tfar, 1.0f - 1e-4f);
    EXPECT_LT(glm::length(s.org + s.dir - point.position), 1e-5f);
  }

  scene.lights = {sun, point};
  for (const Ray& s : make_ray_set(scene, brute, floor_camera(), RaySet::Shadow, 0)) {
    EXPECT_EQ(s.tfar, kInfinity);
    EXPECT_LT(glm::length(s.dir - glm::normalize(-sun.direction)), 1e-6f);
  }
}

TEST(RaySets, AreaLightsComeBeforePunctualLights) {
  Scene scene = floor_scene();
  const std::uint32_t lamp = test::add_material(scene, test::emissive_material(glm::vec3(5.0f)));
  test::add_square_z(scene, 10, 10, 4, 0.5f, false, lamp);  // outside the view, facing down
  PunctualLight point;
  point.position = glm::vec3(0, 0, 3);
  scene.lights = {point};
  const BruteForce brute(scene.triangles);
  for (const Ray& s : make_ray_set(scene, brute, floor_camera(), RaySet::Shadow, 0)) {
    const glm::vec3 target = s.org + s.dir;
    EXPECT_NEAR(target.z, 4.0f, 1e-4f);
    EXPECT_NEAR(target.x, 10.0f, 0.5001f);
    EXPECT_NEAR(target.y, 10.0f, 0.5001f);
  }
}

TEST(RaySets, ShadowRaysNeedALight) {
  const Scene scene = floor_scene();
  const BruteForce brute(scene.triangles);
  try {
    make_ray_set(scene, brute, floor_camera(), RaySet::Shadow, 0);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("floor has no light"), std::string::npos) << e.what();
  }
  EXPECT_EQ(make_ray_set(scene, brute, floor_camera(), RaySet::Diffuse, 0).size(), 256u);
}

TEST(RaySets, SetsDependOnlyOnTheSeedNotOnThreadsOrAccelerator) {
  const Scene scene = cornell();
  const PinholeCamera camera = cornell_camera(scene, 64);
  const BruteForce brute(scene.triangles);
  const std::unique_ptr<Accelerator> kd = make_accelerator("kdtree", scene.triangles);
  for (RaySet set : {RaySet::Primary, RaySet::Diffuse, RaySet::Shadow}) {
    const std::vector<Ray> reference = make_ray_set(scene, brute, camera, set, 3);
    std::vector<Ray> one_thread, two_threads;
    tbb::task_arena(1).execute([&] { one_thread = make_ray_set(scene, *kd, camera, set, 3); });
    tbb::task_arena(2).execute([&] { two_threads = make_ray_set(scene, *kd, camera, set, 3); });
    EXPECT_TRUE(same_bits(reference, one_thread)) << ray_set_name(set);
    EXPECT_TRUE(same_bits(reference, two_threads)) << ray_set_name(set);
    const std::vector<Ray> other_seed = make_ray_set(scene, brute, camera, set, 4);
    EXPECT_EQ(same_bits(reference, other_seed), set == RaySet::Primary) << ray_set_name(set);
  }
}

}  // namespace
}  // namespace lancer
