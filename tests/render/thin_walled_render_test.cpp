// Thin walls against volume boundaries in the integrators (bsdf_thin_walled_test.cpp tests
// the BSDF itself). KHR_materials_transmission: a thin wall does not bend light
// ("Refraction": no macroscopic refraction); KHR_materials_volume: thicknessFactor > 0 makes
// the surface a volume boundary that refracts by the ior.
//  - Path tracer: a smooth glass quad at 45 degrees between a pinhole camera looking straight
//    down and a one-sided emitter covering the half-plane x < 0. Each pixel's expected value
//    follows from where its four corner rays land on the emitter's plane:
//      thin wall: straight on, (1 - F) where they land at x < 0, exactly 0 elsewhere (the
//      reflection leaves sideways into nothing);
//      slab of two such quads, thickness d, as a volume: the path that crosses the slab once
//      lands Snell's lateral shift s = d sin(45 - 28.1 degrees) / cos(28.1 degrees) = 0.165
//      towards -x; each further round trip inside moves it down the slope, towards +x. A
//      pixel whose first L paths (k = 0 .. L - 1 round trips) land at x < 0 gets
//      (1 - F)^2 (1 - F^(2L)) / (1 - F^2) (for L -> infinity the Airy sum (1 - F) / (1 + F)).
//    Pixels whose corners land on different sides of a boundary are skipped; every other
//    pixel must match within 6 standard deviations of its Bernoulli noise, and each region's
//    mean within 5. A one-pixel offset of the image changes some pixel by about 35 deviations.
//    And only a volume attenuates (Beer-Lambert inside a box one unit thick).
//  - Whitted: a ray through a thin wall goes on in a straight line, not along Snell's
//    direction, and seen from its back at 60 degrees a thin wall reflects F, where a volume
//    boundary reflects totally.
//  - scenes/cornell-box-spheres.gltf: its glass sphere is a volume.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "render/fresnel.h"
#include "render/lights.h"
#include "render/renderer.h"
#include "render/shading_inputs.h"
#include "render/whitted.h"
#include "render_test_scenes.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "test_paths.h"

namespace lancer {
namespace {

using test::add_material;

constexpr float kIor = 1.5f;
constexpr float kEmitterZ = -3.0f;
constexpr int kSize = 32;
constexpr int kSpp = 128;

// A black, non-reflecting emitter of radiance 1 over x < 0 in the plane z = kEmitterZ, facing +z.
void add_half_plane_emitter(Scene& scene) {
  Material m = test::emissive_material(glm::vec3(1.0f));
  m.specular = 0.0f;
  const std::uint32_t id = add_material(scene, m);
  append_quad(scene, {-40, -40, kEmitterZ}, {0, -40, kEmitterZ}, {0, 40, kEmitterZ}, {-40, 40, kEmitterZ}, id);
}

// The plane x + z = offset * sqrt 2 (unit normal (1, 0, 1) / sqrt 2), its front facing along
// the normal (towards the camera) or away from it.
void add_tilted_quad(Scene& scene, float offset, bool facing_camera, std::uint32_t material) {
  const glm::vec3 shift = offset * glm::normalize(glm::vec3(1, 0, 1));
  const glm::vec3 a = glm::vec3(-1.5f, -1.5f, 1.5f) + shift, b = glm::vec3(1.5f, -1.5f, -1.5f) + shift,
                  c = glm::vec3(1.5f, 1.5f, -1.5f) + shift, d = glm::vec3(-1.5f, 1.5f, 1.5f) + shift;
  if (facing_camera)
    append_quad(scene, a, b, c, d, material);
  else
    append_quad(scene, a, d, c, b, material);
}

PinholeCamera looking_down() { return PinholeCamera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.1f, kSize, kSize); }

ImageRGB render_path(const Scene& scene) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = kSize;
  s.height = kSize;
  s.spp = kSpp;
  s.integrator = IntegratorKind::Path;
  s.max_depth = 64;
  s.seed = 5;
  RenderStats stats;
  return render_image(scene, kd, looking_down(), s, stats);
}

// Where a ray lands on the emitter's plane after passing the optics, for the path that
// crosses a slab of thickness d (2k + 1) times; d = 0: a thin wall, straight on.
float landing_x(const Ray& ray, float d, int k) {
  const glm::vec3 n = glm::normalize(glm::vec3(1, 0, 1));
  const glm::vec3 dir = glm::normalize(ray.dir);
  glm::vec3 p = ray.org;
  if (d > 0.0f) {
    p += dir * (-glm::dot(ray.org, n) / glm::dot(dir, n));  // onto the plane x + z = 0
    const float eta = 1.0f / kIor, cos_i = -glm::dot(dir, n);
    const float cos_t = std::sqrt(1.0f - eta * eta * (1.0f - cos_i * cos_i));
    const glm::vec3 inside = eta * dir + (eta * cos_i - cos_t) * n;
    const glm::vec3 along = (inside - glm::dot(inside, n) * n) * (d / cos_t);  // per crossing
    p += -d * n + static_cast<float>(2 * k + 1) * along;
  }
  return p.x + dir.x * ((kEmitterZ - p.z) / dir.z);
}

struct Expectation {
  bool clean = false;    // every corner of the pixel lands in the same region
  int region = 0;        // how many paths reach the emitter: thin 0 or 1, slab L
  bool shifted = false;  // lit, but a straight line would have landed at x > 0
  double value = 0.0;
};

Expectation expect_pixel(const PinholeCamera& cam, int i, int j, float d) {
  constexpr float kMargin = 0.003f;  // about an eighth of a pixel on the emitter's plane
  const Ray centre = cam.generate(i + 0.5f, j + 0.5f);
  const float cos_i = glm::dot(-glm::normalize(centre.dir), glm::normalize(glm::vec3(1, 0, 1)));
  const double F = exact_dielectric_fresnel(cos_i, kIor);
  Expectation e;
  int first = -1;
  bool clean = true;
  for (int c = 0; c < 4; ++c) {
    const Ray r = cam.generate(static_cast<float>(i + c % 2), static_cast<float>(j + c / 2));
    // Paths with more round trips land further towards +x: count those at x < 0.
    int region = 0;
    while (region < 64 && landing_x(r, d, region) < 0.0f) ++region;
    clean = clean && std::abs(landing_x(r, d, region)) > kMargin &&
            (region == 0 || std::abs(landing_x(r, d, region - 1)) > kMargin);
    if (d == 0.0f) region = std::min(region, 1);  // a thin wall has one path through
    clean = clean && (first < 0 || region == first);
    first = region;
  }
  e.clean = clean;
  e.region = first;
  if (d == 0.0f) {
    e.value = first * (1.0 - F);
  } else {
    e.value = (1.0 - F) * (1.0 - F) * (1.0 - std::pow(F, 2 * first)) / (1.0 - F * F);
  }
  e.shifted = first > 0 && landing_x(centre, 0.0f, 0) > 0.0f;
  return e;
}

struct RegionSums {
  int pixels = 0;
  double sum = 0.0, expected = 0.0, variance = 0.0;
};

// Checks every clean pixel and each region's mean; returns the clean pixels per region.
std::vector<RegionSums> check_image(const ImageRGB& image, float d, const char* what, int* shifted = nullptr) {
  const PinholeCamera cam = looking_down();
  std::vector<RegionSums> regions(8);
  int worst_i = -1, worst_j = -1;
  double worst_z = 0.0;
  for (int j = 0; j < kSize; ++j)
    for (int i = 0; i < kSize; ++i) {
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(image.rgb[3 * (j * kSize + i) + c])) << what;
      const Expectation e = expect_pixel(cam, i, j, d);
      if (!e.clean || e.region >= static_cast<int>(regions.size())) continue;
      const double v = image.at(i, j).x;  // the emitter and glass are grey: one channel will do
      const double var = e.value * (1.0 - e.value) / kSpp;
      const double z = std::abs(v - e.value) / (std::sqrt(var) + 1e-4 / 6.0);
      if (z > worst_z) worst_z = z, worst_i = i, worst_j = j;
      EXPECT_LE(z, 6.0) << what << ": pixel (" << i << ", " << j << ") is " << v << ", expected " << e.value;
      RegionSums& r = regions[e.region];
      ++r.pixels;
      r.sum += v;
      r.expected += e.value;
      r.variance += var;
      if (shifted && e.shifted) ++*shifted;
    }
  for (size_t k = 0; k < regions.size(); ++k) {
    const RegionSums& r = regions[k];
    if (r.pixels == 0) continue;
    EXPECT_NEAR(r.sum / r.pixels, r.expected / r.pixels, 5.0 * std::sqrt(r.variance) / r.pixels + 1e-5)
        << what << ", region " << k << " (" << r.pixels << " pixels)";
    std::printf("%s region %zu: %3d pixels, mean %.5f expected %.5f\n", what, k, r.pixels, r.sum / r.pixels,
                r.expected / r.pixels);
  }
  std::printf("%s: worst pixel (%d, %d) at %.2f standard deviations\n", what, worst_i, worst_j, worst_z);
  return regions;
}

TEST(ThinWallPath, QuadTransmitsOneMinusFWithoutMovingTheImage) {
  for (bool facing_camera : {true, false}) {
    Scene scene;
    add_half_plane_emitter(scene);
    add_tilted_quad(scene, 0.0f, facing_camera, add_material(scene, test::glass_material(kIor)));
    ASSERT_EQ(scene.materials.back().thickness, 0.0f);  // no KHR_materials_volume: thin-walled
    int shifted = 0;
    const auto regions =
        check_image(render_path(scene), 0.0f, facing_camera ? "thin, front" : "thin, back", &shifted);
    EXPECT_GT(regions[0].pixels, 300);  // dark
    EXPECT_GT(regions[1].pixels, 300);  // lit
    EXPECT_EQ(shifted, 0);
  }
}

TEST(ThinWallPath, SlabWithThicknessRefractsAndShiftsTheImage) {
  constexpr float kThickness = 0.5f;
  Scene scene;
  add_half_plane_emitter(scene);
  Material glass = test::glass_material(kIor);
  glass.thickness = kThickness;  // KHR_materials_volume: a volume boundary
  const std::uint32_t id = add_material(scene, glass);
  add_tilted_quad(scene, 0.0f, true, id);
  add_tilted_quad(scene, -kThickness, false, id);  // the far face, front facing out of the slab
  int shifted = 0;
  const auto regions = check_image(render_path(scene), kThickness, "slab", &shifted);
  EXPECT_GT(regions[0].pixels, 200);  // dark
  EXPECT_GT(regions[1].pixels, 200);  // one path through
  EXPECT_GT(regions[2].pixels, 100);  // and one more after a round trip inside
  // Snell's lateral shift of 0.165 is 6.6 pixels: at least four columns are lit that a thin
  // wall leaves dark.
  EXPECT_GE(shifted, 4 * kSize);
}

// A closed box one unit thick at normal incidence, with KHR_materials_volume's attenuation
// colour 0.5 at distance 1: as a volume it absorbs half on each crossing, T = (1 - R)^2 a /
// (1 - R^2 a^2) with a = 0.5; as thin walls it encloses no medium and transmits the Airy sum
// of two walls, (1 - R) / (1 + R).
TEST(ThinWallPath, OnlyAVolumeAttenuates) {
  for (float thickness : {0.0f, 1.0f}) {
    Scene scene;
    Material glass = test::glass_material(kIor);
    glass.thickness = thickness;
    glass.attenuation_distance = 1.0f;
    glass.attenuation_color = glm::vec3(0.5f);
    append_box(scene, {{-5, -5, -0.5f}, {5, 5, 0.5f}}, add_material(scene, glass));
    add_half_plane_emitter(scene);
    const KdTree kd(scene.triangles);
    RenderSettings s;
    s.width = s.height = 16;
    s.spp = 256;
    s.integrator = IntegratorKind::Path;
    s.max_depth = 64;
    s.seed = 3;
    RenderStats stats;
    // Looking down at x = -1, well inside the emitter's half-plane x < 0.
    const PinholeCamera cam = PinholeCamera::look_at({-1, 0, 5}, {-1, 0, 0}, {0, 1, 0}, 0.02f, 16, 16);
    const ImageRGB image = render_image(scene, kd, cam, s, stats);
    double sum = 0.0, sum2 = 0.0;
    const std::size_t n = image.rgb.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
      sum += image.rgb[3 * i];
      sum2 += static_cast<double>(image.rgb[3 * i]) * image.rgb[3 * i];
    }
    const double mean = sum / n, stderr_ = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    const double R = 0.04, a = thickness > 0.0f ? 0.5 : 1.0;
    const double expected = (1 - R) * (1 - R) * a / (1 - R * R * a * a);
    EXPECT_NEAR(mean, expected, 5.0 * stderr_ + 1e-4) << "thickness " << thickness;
  }
}

// The shipped Cornell box's glass sphere is solid glass: KHR_materials_volume makes it a
// volume boundary (without it, it would render as a thin-walled bubble).
TEST(ThinWallScenes, CornellGlassSphereIsAVolume) {
  const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  int transmissive = 0;
  for (const Material& m : scene.materials) {
    if (m.transmission <= 0.0f) continue;
    ++transmissive;
    EXPECT_FALSE(is_thin_walled(m)) << m.name;
    EXPECT_FLOAT_EQ(m.thickness, 0.2f) << m.name << ": the sphere's diameter";
  }
  EXPECT_EQ(transmissive, 1);
}

// ---- Whitted ----------------------------------------------------------------------------

glm::vec3 whitted_radiance(const Scene& scene, const Ray& ray) {
  const BruteForce accel(scene.triangles);
  const AreaLights area(scene);
  const WhittedIntegrator whitted(scene, accel, area, 8, 4);
  SobolSampler sampler(0, 0, 0, 1);
  std::uint64_t rays = 0;
  return whitted.radiance(ray, sampler, rays);
}

// A ray at 45 degrees through a smooth wall at the origin, and a narrow emissive strip one
// unit below it, either on the straight line (x = 1) or where Snell's law would send it.
TEST(ThinWallWhitted, GoesOnInAStraightLine) {
  const float snell_x = std::tan(std::asin(std::sqrt(0.5f) / kIor));
  const float F = exact_dielectric_fresnel(std::sqrt(0.5f), kIor);
  const glm::vec3 dir = glm::normalize(glm::vec3(1, 0, -1));
  for (float thickness : {0.0f, 1.0f}) {
    for (float strip_x : {1.0f, snell_x}) {
      Scene scene;
      Material glass = test::glass_material(kIor);
      glass.thickness = thickness;
      test::add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, glass));
      const std::uint32_t strip = add_material(scene, test::emissive_material(glm::vec3(1.0f)));
      append_quad(scene, {strip_x - 0.01f, -1, -1}, {strip_x + 0.01f, -1, -1}, {strip_x + 0.01f, 1, -1},
                  {strip_x - 0.01f, 1, -1}, strip);
      const bool hit = (thickness == 0.0f) == (strip_x == 1.0f);
      const glm::vec3 L = whitted_radiance(scene, test::ray_from(-dir, dir));
      EXPECT_NEAR(L.x, hit ? 1.0f - F : 0.0f, 1e-5f) << "thickness " << thickness << ", strip at " << strip_x;
    }
  }
}

// From below (the back side) at 60 degrees, beyond the critical angle of 41.8 degrees.
TEST(ThinWallWhitted, BackSideReflectsFresnelNotTotally) {
  const glm::vec3 dir(std::sin(1.0472f), 0.0f, std::cos(1.0472f));  // upwards
  for (float thickness : {0.0f, 1.0f}) {
    Scene scene;
    Material glass = test::glass_material(kIor);
    glass.thickness = thickness;
    test::add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, glass));
    test::add_square_z(scene, 0, 0, -3, 50, true, add_material(scene, test::emissive_material(glm::vec3(1.0f))));
    const glm::vec3 L = whitted_radiance(scene, test::ray_from(-0.5f * dir, dir));
    const float expected = thickness == 0.0f ? exact_dielectric_fresnel(std::cos(1.0472f), kIor) : 1.0f;
    EXPECT_NEAR(L.x, expected, 1e-5f) << "thickness " << thickness;
  }
}

}  // namespace
}  // namespace lancer
