// Punctual lights (KHR_lights_punctual) and emissive triangles as area lights.
#include "render/lights.h"

#include <array>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/sampler.h"
#include "render/surface.h"
#include "render/whitted.h"
#include "render_test_scenes.h"
#include "scene/scene_builder.h"

namespace lancer {
namespace {

using test::add_material;
using test::add_square_z;
using test::ray_from;

constexpr float kPi = 3.14159265358979f;

TEST(PunctualLights, PointLightInverseSquare) {
  PunctualLight l;
  l.position = {1, 2, 3};
  l.intensity = 8.0f;
  l.color = {1.0f, 0.5f, 0.25f};
  const PunctualIncidence in = illuminate(l, {1, 2, 1});
  EXPECT_EQ(in.wi, glm::vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(in.distance, 2.0f);
  EXPECT_FLOAT_EQ(in.irradiance.x, 2.0f);
  EXPECT_FLOAT_EQ(in.irradiance.y, 1.0f);
  EXPECT_FLOAT_EQ(in.irradiance.z, 0.5f);
}

TEST(PunctualLights, PointLightAtThePointGivesNothing) {
  PunctualLight l;
  l.position = {1, 2, 3};
  const PunctualIncidence in = illuminate(l, {1, 2, 3});
  EXPECT_EQ(in.irradiance, glm::vec3(0.0f));
}

TEST(PunctualLights, RangeWindow) {
  PunctualLight l;
  l.position = {0, 0, 2};
  l.intensity = 4.0f;
  l.range = 4.0f;
  // Window 1 - (2/4)^4 = 0.9375, times 4 / 2^2.
  EXPECT_FLOAT_EQ(illuminate(l, {0, 0, 0}).irradiance.x, 0.9375f);
  EXPECT_EQ(illuminate(l, {0, 0, -3}).irradiance.x, 0.0f);  // beyond the range
}

TEST(PunctualLights, DirectionalLightIsConstant) {
  PunctualLight l;
  l.type = LightType::Directional;
  l.direction = {0, -2, 0};  // shining down, not normalised
  l.intensity = 3.0f;
  for (const glm::vec3 p : {glm::vec3(0), glm::vec3(100, -50, 7)}) {
    const PunctualIncidence in = illuminate(l, p);
    EXPECT_EQ(in.wi, glm::vec3(0, 1, 0));
    EXPECT_EQ(in.irradiance, glm::vec3(3.0f));
    EXPECT_TRUE(std::isinf(in.distance));
  }
}

TEST(PunctualLights, SpotFalloffBetweenTheCones) {
  PunctualLight l;
  l.type = LightType::Spot;
  l.position = {0, 0, 0};
  l.direction = {0, 0, -1};
  l.intensity = 1.0f;
  l.inner_cone = 0.2f;
  l.outer_cone = 0.6f;
  auto at_angle = [&](float a) { return illuminate(l, {std::sin(a), 0.0f, -std::cos(a)}).irradiance.x; };
  EXPECT_FLOAT_EQ(at_angle(0.0f), 1.0f);
  EXPECT_FLOAT_EQ(at_angle(0.19f), 1.0f);
  EXPECT_EQ(at_angle(0.61f), 0.0f);
  EXPECT_EQ(at_angle(2.0f), 0.0f);
  // Between the cones: ((cos a - cos outer) / (cos inner - cos outer))^2.
  const float a = 0.4f;
  const float t = (std::cos(a) - std::cos(0.6f)) / (std::cos(0.2f) - std::cos(0.6f));
  EXPECT_NEAR(at_angle(a), t * t, 1e-5f);
  // Falls off monotonically.
  EXPECT_GT(at_angle(0.3f), at_angle(0.4f));
  EXPECT_GT(at_angle(0.4f), at_angle(0.5f));
}

TEST(AreaLights, OnlyEmissiveTrianglesWithPowerPickedByPower) {
  Scene scene;
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(glm::vec3(0.5f))));
  add_square_z(scene, 0, 0, 2, 1, false, add_material(scene, test::emissive_material(glm::vec3(1.0f))));
  add_square_z(scene, 5, 0, 2, 0.5f, false, add_material(scene, test::emissive_material(glm::vec3(3.0f))));
  const AreaLights lights(scene);
  ASSERT_EQ(lights.size(), 4u);
  // Powers: 2 x area 2 x 1, 2 x area 0.5 x 3 -> 4 : 3.
  EXPECT_NEAR(lights.pick_probability(0), 2.0f / 7.0f, 1e-6f);
  EXPECT_NEAR(lights.pick_probability(3), 1.5f / 7.0f, 1e-6f);
  EXPECT_EQ(lights.light(0).prim, 2u);
  EXPECT_EQ(lights.light(0).normal, glm::vec3(0, 0, -1));
  EXPECT_FLOAT_EQ(lights.light(0).area, 2.0f);
}

TEST(AreaLights, SamplesAreUniformOnTheTriangle) {
  Scene scene;
  const glm::vec3 p[3] = {{0, 0, 0}, {4, 0, 0}, {0, 2, 0}};
  scene.materials.push_back(test::emissive_material(glm::vec3(1.0f)));
  SceneBuilder(scene, "tri").add_triangle(p, 0, 0);
  const AreaLights lights(scene);
  ASSERT_EQ(lights.size(), 1u);
  // The parts y >= 1 and x >= 2 are copies of the triangle scaled by 1/2: a quarter of the
  // area each, so uniform samples fall in y < 1 and in x < 2 with probability 3/4.
  int low = 0, left = 0;
  const int n = 40000;
  for (int i = 0; i < n; ++i) {
    const PixelSampler s(static_cast<std::uint32_t>(i), 0, 0, 5);
    const AreaLightSample ls = lights.sample(s.get(0), s.get(1), s.get(2));
    ASSERT_GE(ls.point.x, 0.0f);
    ASSERT_GE(ls.point.y, 0.0f);
    ASSERT_LE(ls.point.x / 4.0f + ls.point.y / 2.0f, 1.0f + 1e-6f);
    EXPECT_FLOAT_EQ(ls.pdf_area, 1.0f / 4.0f);
    low += ls.point.y < 1.0f;
    left += ls.point.x < 2.0f;
  }
  // Binomial standard deviation sqrt(n p (1 - p)) = 86.6; allow 5 sigma.
  EXPECT_NEAR(low, 0.75 * n, 433);
  EXPECT_NEAR(left, 0.75 * n, 433);
}

// Irradiance at the origin (normal +z) from a square [x0, x1] x [y0, y1] at height h
// emitting radiance 1 downwards: E = integral of h^2 / r^4 dA, by midpoint quadrature.
double square_irradiance(double x0, double x1, double y0, double y1, double h) {
  const int n = 1000;
  const double dx = (x1 - x0) / n, dy = (y1 - y0) / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = x0 + (i + 0.5) * dx, y = y0 + (j + 0.5) * dy;
      const double r2 = x * x + y * y + h * h;
      sum += h * h / (r2 * r2);
    }
  return sum * dx * dy;
}

// Radiance of a diffuse floor point at the origin seen from straight above.
glm::vec3 floor_radiance(const Scene& scene, int light_samples) {
  const BruteForce accel(scene.triangles);
  const AreaLights lights(scene);
  const WhittedIntegrator whitted(scene, accel, lights, 4, light_samples);
  SobolSampler sampler(1, 2, 3, 4);
  std::uint64_t rays = 0;
  return whitted.radiance(ray_from({0.01f, 0.02f, 0.5f}, {0, 0, -1}), sampler, rays);
}

TEST(AreaLights, SmallSquareGivesLTimesAOverHSquared) {
  Scene scene;
  const float albedo = 0.6f, L = 100.0f, side = 0.1f, h = 1.0f;
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(glm::vec3(albedo))));
  add_square_z(scene, 0, 0, h, 0.5f * side, false, add_material(scene, test::emissive_material(glm::vec3(L))));
  const float E = L * side * side / (h * h);
  const glm::vec3 got = floor_radiance(scene, 64);
  EXPECT_NEAR(got.x, albedo / kPi * E, 0.01f * albedo / kPi * E);
}

TEST(AreaLights, LargeLightsMatchQuadrature) {
  // Two lights of different radiance and size, one partly off to the side: the
  // power-proportional choice and the area pdf must combine to the exact integral.
  Scene scene;
  const float albedo = 0.5f;
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(glm::vec3(albedo))));
  add_square_z(scene, 0, 0, 1, 1, false, add_material(scene, test::emissive_material(glm::vec3(2.0f))));
  add_square_z(scene, 2, 1, 1.5f, 0.5f, false, add_material(scene, test::emissive_material(glm::vec3(7.0f))));
  const double E = 2.0 * square_irradiance(-1, 1, -1, 1, 1.0) + 7.0 * square_irradiance(1.5, 2.5, 0.5, 1.5, 1.5);
  const double want = albedo / kPi * E;
  const glm::vec3 got = floor_radiance(scene, 40000);
  // The estimator's relative standard deviation here is below 0.5% for 40000 samples.
  EXPECT_NEAR(got.x, want, 0.02 * want);
}

TEST(AreaLights, LightsFacingAwayAndBlockedLightsGiveNothing) {
  Scene scene;
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(glm::vec3(0.5f))));
  // Emits upwards, away from the floor.
  add_square_z(scene, 0, 0, 1, 0.5f, true, add_material(scene, test::emissive_material(glm::vec3(5.0f))));
  EXPECT_EQ(floor_radiance(scene, 16), glm::vec3(0.0f));

  Scene blocked;
  add_square_z(blocked, 0, 0, 0, 10, true, add_material(blocked, test::diffuse_material(glm::vec3(0.5f))));
  add_square_z(blocked, 0, 0, 1, 0.5f, false, add_material(blocked, test::emissive_material(glm::vec3(5.0f))));
  EXPECT_GT(floor_radiance(blocked, 16).x, 0.0f);
  add_square_z(blocked, 0, 0, 0.3f, 2.0f, true, 0);  // a large diffuse sheet between
  // The camera ray sees the sheet now; its top is lit, so look at the floor from below the sheet.
  const BruteForce accel(blocked.triangles);
  const AreaLights lights(blocked);
  const WhittedIntegrator whitted(blocked, accel, lights, 4, 16);
  SobolSampler sampler(0, 0, 0, 0);
  std::uint64_t rays = 0;
  EXPECT_EQ(whitted.radiance(ray_from({0.01f, 0.02f, 0.2f}, {0, 0, -1}), sampler, rays), glm::vec3(0.0f));
}

// A 64 x 1 RGB strip, nearest-filtered: the left `black` texels black, the rest white.
int add_strip(Scene& scene, int black) {
  Image image;
  image.width = 64;
  image.height = 1;
  image.channels = 3;
  for (int x = 0; x < 64; ++x)
    for (int c = 0; c < 3; ++c) image.pixels.push_back(x < black ? 0 : 255);
  scene.images.push_back(image);
  Texture texture;
  texture.image = static_cast<int>(scene.images.size() - 1);
  texture.mag_filter = texture.min_filter = kFilterNearest;
  texture.wrap_s = texture.wrap_t = 33071;  // CLAMP_TO_EDGE
  scene.textures.push_back(texture);
  return static_cast<int>(scene.textures.size() - 1);
}

// A unit square emitting radiance 1 times the strip (u along x), at x = cx.
void add_textured_emitter(Scene& scene, float cx, int black) {
  Material m = test::emissive_material(glm::vec3(1.0f));
  m.emissive_texture.texture = add_strip(scene, black);
  const std::uint32_t id = add_material(scene, m);
  SceneBuilder builder(scene, "emitter");
  const glm::vec3 p[4] = {{cx, 0, 0}, {cx + 1, 0, 0}, {cx + 1, 1, 0}, {cx, 1, 0}};
  for (const auto& t : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
    const glm::vec3 corners[3] = {p[t[0]], p[t[1]], p[t[2]]};
    glm::vec2 uvs[3];
    for (int k = 0; k < 3; ++k) uvs[k] = glm::vec2(corners[k].x - cx, corners[k].y);
    CornerAttributes attribs;
    attribs.texcoords = uvs;
    builder.add_triangle(corners, id, 0, attribs);
  }
}

TEST(AreaLights, BlackEmissiveTextureMakesNoLightAndPowerFollowsTheTexture) {
  Scene scene;
  add_textured_emitter(scene, 0.0f, 64);  // black everywhere: not a light
  add_textured_emitter(scene, 2.0f, 0);   // white: the factor's full power
  add_textured_emitter(scene, 4.0f, 32);  // left half black: half of it
  const AreaLights lights(scene);
  ASSERT_EQ(lights.size(), 4u) << "the black square's two triangles are not lights";
  double white = 0.0, half = 0.0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    EXPECT_GE(lights.light(i).prim, 2u);
    (lights.light(i).prim < 4 ? white : half) += lights.pick_probability(i);
  }
  EXPECT_NEAR(half / white, 0.5, 0.05) << "power estimated over the texture";
  EXPECT_EQ(lights.pdf_area(0), 0.0f);
}

}  // namespace
}  // namespace lancer
