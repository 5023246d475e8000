// The path tracer against closed-form answers, within the statistical error each render
// predicts (mean over pixels +- 5 standard errors, plus 1e-4 for float rounding):
//  - white furnace: a white Lambertian sphere inside a closed enclosure that reflects half
//    and emits half: radiance 1 everywhere (L = Le + a L with Le = 1 - a), which takes
//    every bounce, Russian roulette and the MIS of emitter hits to get right;
//  - the same sphere under a uniform environment of radiance 1 (environment sampling);
//  - a Lambertian plane of albedo a under a uniform sky L: radiance a L;
//  - a smooth glass slab (ior 1.5) in front of an emitter: the slab's transmittance with
//    all internal reflections, (1 - R) / (1 + R), R = ((n - 1) / (n + 1))^2;
//  - a perfect mirror (metallic, base colour c) at 45 degrees: Schlick's c + (1 - c)(1 - cos)^5.
//  - four bounces between two such mirrors: every sample the same, no roulette after a delta
//    bounce.
// And no sample is ever NaN or infinite.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "render/environment.h"
#include "render/renderer.h"
#include "image_estimate.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"

namespace lancer {
namespace {

using test::add_material;

using test::Estimate;
using test::estimate;

void expect_radiance(const ImageRGB& image, double expected, const char* what) {
  for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v)) << what;
  for (int c = 0; c < 3; ++c) {
    const Estimate e = estimate(image, c);
    EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4)
        << what << ", channel " << c << ": mean " << e.mean << " +- " << e.stderr_;
  }
}

ImageRGB render_path(const Scene& scene, const PinholeCamera& cam, int spp, const Environment* env = nullptr,
                     int max_depth = 64) {
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = spp;
  s.integrator = IntegratorKind::Path;
  s.max_depth = max_depth;
  s.environment = env;
  s.seed = 11;
  RenderStats stats;
  return render_image(scene, kd, cam, s, stats);
}

// A Lambertian material: no specular layer (KHR_materials_specular factor 0).
Material lambert(float albedo) {
  Material m = test::diffuse_material(glm::vec3(albedo));
  m.specular = 0.0f;
  return m;
}

// An emitter that reflects nothing (black, and no specular layer either).
Material black_emitter(float radiance) {
  Material m = test::emissive_material(glm::vec3(radiance));
  m.specular = 0.0f;
  return m;
}


TEST(PathTracer, WhiteFurnaceInsideAClosedEmitterIsOneEverywhere) {
  Scene scene;
  append_icosphere(scene, {0, 0, 0}, 1.0f, 3, add_material(scene, lambert(1.0f)));
  const std::size_t enclosure = scene.triangle_count();
  Material wall = lambert(0.5f);
  wall.emissive_factor = glm::vec3(0.5f);  // L = 0.5 + 0.5 L  =>  L = 1
  append_icosphere(scene, {0, 0, 0}, 4.0f, 3, add_material(scene, wall));
  test::flip_winding(scene, enclosure);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 1.2f, 24, 24);
  expect_radiance(render_path(scene, cam, 64), 1.0, "furnace");
}

TEST(PathTracer, WhiteSphereUnderAUniformEnvironmentIsOne) {
  Scene scene;
  append_icosphere(scene, {0, 0, 0}, 1.0f, 3, add_material(scene, lambert(1.0f)));
  const Environment env(glm::vec3(1.0f));
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.6f, 24, 24);
  expect_radiance(render_path(scene, cam, 32, &env), 1.0, "sphere in a uniform environment");
}

TEST(PathTracer, LambertianPlaneUnderAUniformSkyIsAlbedoTimesSky) {
  Scene scene;
  test::add_square_z(scene, 0, 0, 0, 1000.0f, true, add_material(scene, lambert(0.4f)));
  const Environment sky(glm::vec3(2.5f));
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 0.5f, 24, 24);
  expect_radiance(render_path(scene, cam, 32, &sky), 0.4 * 2.5, "plane under the sky");
}

TEST(PathTracer, SmoothGlassSlabTransmitsItsFresnelTransmittance) {
  Scene scene;
  Material glass = test::glass_material(1.5f);
  glass.thickness = 1.0f;  // KHR_materials_volume: a solid slab, not a thin-walled box
  append_box(scene, {{-5, -5, -0.5f}, {5, 5, 0.5f}}, add_material(scene, glass));
  test::add_square_z(scene, 0, 0, -3, 100.0f, true, add_material(scene, black_emitter(1.0f)));
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.02f, 16, 16);
  const double R = 0.04;  // ((1.5 - 1) / (1.5 + 1))^2
  expect_radiance(render_path(scene, cam, 256), (1.0 - R) / (1.0 + R), "glass slab");
}

TEST(PathTracer, PerfectMirrorReflectsSchlicksFresnel) {
  Scene scene;
  // A mirror in the plane y = -z (its normal (0, 1, 1) / sqrt 2), seen from +z: the camera
  // rays turn to +y, onto an emitter facing down.
  const std::uint32_t mirror = add_material(scene, test::mirror_material(glm::vec3(0.8f)));
  append_quad(scene, {-50, -50, 50}, {50, -50, 50}, {50, 50, -50}, {-50, 50, -50}, mirror);
  const std::uint32_t light = add_material(scene, black_emitter(1.0f));
  append_quad(scene, {-100, 10, -100}, {100, 10, -100}, {100, 10, 100}, {-100, 10, 100}, light);  // facing -y
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.02f, 16, 16);
  const double c = 0.8, cos45 = std::sqrt(0.5);
  expect_radiance(render_path(scene, cam, 16), c + (1.0 - c) * std::pow(1.0 - cos45, 5.0), "mirror");
}

// Russian roulette is not played after a delta event while the throughput is above 1/16
// (path_rules::roulette_after): a path through mirrors alone brings every sample the same
// light. Each camera ray bounces four times between two mirrors (base colour 0.6) at 45
// degrees before it meets the emitter, so the throughput is about 0.2 when the roulette
// would first be played; with it, about half of the samples would be 0 and the rest twice
// the answer.
TEST(PathTracer, NoRouletteAfterMirrorBounces) {
  Scene scene;
  const std::uint32_t mirror = add_material(scene, test::mirror_material(glm::vec3(0.6f)));
  append_quad(scene, {-10, 1, -100}, {8, 1, -100}, {8, 1, 100}, {-10, 1, 100}, mirror);
  append_quad(scene, {-10, -1, -100}, {8, -1, -100}, {8, -1, 100}, {-10, -1, 100}, mirror);
  Material emitter = black_emitter(1.0f);
  emitter.double_sided = true;
  append_quad(scene, {8, -2, -100}, {8, 2, -100}, {8, 2, 100}, {8, -2, 100}, add_material(scene, emitter));
  // Along (1, 1, 0): mirrors met at x = 1, 3, 5 and 7, the emitter at x = 8.
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 0}, {1, 1, 0}, {0, 0, 1}, 0.02f, 8, 8);
  const ImageRGB image = render_path(scene, cam, 16);
  const double c = 0.6, f = c + (1.0 - c) * std::pow(1.0 - std::sqrt(0.5), 5.0), expected = std::pow(f, 4.0);
  for (float v : image.rgb) ASSERT_NEAR(v, expected, 2e-3 * expected) << "every sample the same: " << expected;
}

// ... and once the throughput is below 1/16, it is: a path caught between two facing mirrors
// of base colour 0.5 (nothing else in the scene) ends within a few bounces of that, not at
// the bounce limit of 64. Without the roulette every camera ray would take 64 bounces.
TEST(PathTracer, PathsBetweenDimMirrorsEndLongBeforeTheBounceLimit) {
  Scene scene;
  const std::uint32_t mirror = add_material(scene, test::mirror_material(glm::vec3(0.5f)));
  append_quad(scene, {-100, 1, -100}, {100, 1, -100}, {100, 1, 100}, {-100, 1, 100}, mirror);
  append_quad(scene, {-100, -1, -100}, {100, -1, -100}, {100, -1, 100}, {-100, -1, 100}, mirror);
  const PinholeCamera cam = PinholeCamera::look_at({0, 0, 0}, {0.01f, 1, 0}, {0, 0, 1}, 0.02f, 8, 8);
  const KdTree kd(scene.triangles);
  RenderSettings s;
  s.width = cam.width();
  s.height = cam.height();
  s.spp = 16;
  s.integrator = IntegratorKind::Path;
  s.max_depth = 64;
  RenderStats stats;
  render_image(scene, kd, cam, s, stats);
  const double rays_per_sample = double(stats.rays) / double(stats.primary_rays);
  // The throughput 0.5^k is below 1/16 from the fifth bounce on; each roulette then keeps
  // at most a quarter of the paths.
  EXPECT_LT(rays_per_sample, 12.0);
}

}  // namespace
}  // namespace lancer
