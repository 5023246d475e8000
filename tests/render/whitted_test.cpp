// The Whitted integrator against closed-form answers on hand-built scenes.
#include "render/whitted.h"

#include "render/fresnel.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/lights.h"
#include "render/shading_inputs.h"
#include "render/color.h"
#include "render/texture.h"
#include "scene/scene_builder.h"
#include "render_test_scenes.h"

namespace lancer {
namespace {

using test::add_material;
using test::add_square_z;
using test::ray_from;

constexpr float kPi = 3.14159265358979f;

// Radiance along `ray` in `scene`, with the oracle accelerator.
glm::vec3 radiance(const Scene& scene, const Ray& ray, int max_depth = 8, int light_samples = 4,
                   std::uint64_t* rays_out = nullptr) {
  const BruteForce accel(scene.triangles);
  const AreaLights area(scene);
  const WhittedIntegrator whitted(scene, accel, area, max_depth, light_samples);
  SobolSampler sampler(0, 0, 0, 1);
  std::uint64_t rays = 0;
  const glm::vec3 L = whitted.radiance(ray, sampler, rays);
  if (rays_out) *rays_out = rays;
  return L;
}

void expect_rel(const glm::vec3& got, const glm::vec3& want, float rel) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], rel * std::fabs(want[c])) << "channel " << c;
}

PunctualLight point_light(const glm::vec3& pos, float intensity, const glm::vec3& color = glm::vec3(1.0f)) {
  PunctualLight l;
  l.type = LightType::Point;
  l.position = pos;
  l.intensity = intensity;
  l.color = color;
  return l;
}

// A 20 x 20 diffuse floor at z = 0 lit by a point light at height h above the origin.
struct LitFloor {
  Scene scene;
  glm::vec3 albedo{0.5f, 0.25f, 0.8f};
  float intensity = 10.0f;
  float h = 2.0f;
  LitFloor() {
    add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(albedo)));
    scene.lights.push_back(point_light({0, 0, h}, intensity));
  }
};

TEST(Whitted, PointLightAtTheFoot) {
  LitFloor f;
  const glm::vec3 L = radiance(f.scene, ray_from({0, 0, 5}, {0, 0, -1}));
  expect_rel(L, f.albedo / kPi * f.intensity / (f.h * f.h), 1e-4f);
}

TEST(Whitted, PointLightOffAxisHasCosineOverRSquared) {
  LitFloor f;
  const float x = 1.5f;
  const float r2 = f.h * f.h + x * x;
  const float cos_theta = f.h / std::sqrt(r2);
  const glm::vec3 L = radiance(f.scene, ray_from({x, 0, 5}, {0, 0, -1}));
  expect_rel(L, f.albedo / kPi * f.intensity * cos_theta / r2, 1e-4f);
  // The camera direction does not matter for a Lambertian surface.
  const glm::vec3 oblique = radiance(f.scene, ray_from({x + 3, 0, 3}, glm::normalize(glm::vec3(-1, 0, -1))));
  expect_rel(oblique, L, 1e-4f);
}

TEST(Whitted, PointLightColourAndBackSide) {
  LitFloor f;
  f.scene.lights[0].color = {1.0f, 0.5f, 0.0f};
  const glm::vec3 L = radiance(f.scene, ray_from({0, 0, 5}, {0, 0, -1}));
  expect_rel(L, f.albedo * glm::vec3(1.0f, 0.5f, 0.0f) / kPi * f.intensity / (f.h * f.h), 1e-4f);
  // Seen from below, the floor's lower side faces away from the light.
  EXPECT_EQ(radiance(f.scene, ray_from({0, 0, -5}, {0, 0, 1})), glm::vec3(0.0f));
}

TEST(Whitted, OccluderCastsAShadow) {
  LitFloor f;
  // A small horizontal triangle halfway between the light (0, 0, 2) and the point (3, 0, 0).
  const glm::vec3 tri[3] = {{1.3f, -0.2f, 1.0f}, {1.7f, -0.2f, 1.0f}, {1.5f, 0.3f, 1.0f}};
  SceneBuilder(f.scene, "occluder").add_triangle(tri, 0, 99);
  EXPECT_EQ(radiance(f.scene, ray_from({3, 0, 5}, {0, 0, -1})), glm::vec3(0.0f));
  // The mirrored point is lit: the shadow comes from the occluder, not from the geometry.
  EXPECT_GT(radiance(f.scene, ray_from({-3, 0, 5}, {0, 0, -1})).x, 0.0f);
}

TEST(Whitted, EmissiveQuadShowsItsEmissionOnTheFrontOnly) {
  Scene scene;
  const glm::vec3 e(2.0f, 3.0f, 4.0f);
  add_square_z(scene, 0, 0, 0, 1, true, add_material(scene, test::emissive_material(e, 5.0f)));
  EXPECT_EQ(radiance(scene, ray_from({0.3f, 0.2f, 4}, {0, 0, -1})), e * 5.0f);
  EXPECT_EQ(radiance(scene, ray_from({0.3f, 0.2f, -4}, {0, 0, 1})), glm::vec3(0.0f));
}

TEST(Whitted, MirrorAtNormalIncidenceShowsBaseColourTimesEmission) {
  Scene scene;
  const glm::vec3 base(0.9f, 0.6f, 0.3f), e(4.0f, 2.0f, 1.0f);
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::mirror_material(base)));
  add_square_z(scene, 0, 0, 3, 10, false, add_material(scene, test::emissive_material(e)));
  const Ray r = ray_from({0.1f, 0.2f, 1}, {0, 0, -1});
  expect_rel(radiance(scene, r), base * e, 1e-6f);
  // With no bounce allowed the mirror is black.
  EXPECT_EQ(radiance(scene, r, 0), glm::vec3(0.0f));
}

TEST(Whitted, MirrorFollowsSchlickAtAnAngle) {
  Scene scene;
  const glm::vec3 base(0.5f, 0.5f, 0.5f), e(1.0f);
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::mirror_material(base)));
  add_square_z(scene, 0, 0, 3, 30, false, add_material(scene, test::emissive_material(e)));
  const float angle = 1.2f;  // from the normal
  const glm::vec3 dir(std::sin(angle), 0.0f, -std::cos(angle));
  const float m = 1.0f - std::cos(angle);
  expect_rel(radiance(scene, ray_from(-dir, dir)), base + (1.0f - base) * std::pow(m, 5.0f), 1e-5f);
}

TEST(Whitted, DielectricFresnelValues) {
  // Normal incidence on glass: ((1.5 - 1) / (1.5 + 1))^2 = 0.04.
  EXPECT_NEAR(exact_dielectric_fresnel(1.0f, 1.5f), 0.04f, 1e-7f);
  // 45 degrees on glass: Rs = 0.0920, Rp = 0.0085 (Hecht, Optics, fig. 4.48), mean 0.0502.
  EXPECT_NEAR(exact_dielectric_fresnel(std::sqrt(0.5f), 1.5f), 0.05025f, 5e-5f);
  // Leaving glass beyond the critical angle asin(1/1.5) = 41.8 degrees: total reflection.
  EXPECT_EQ(exact_dielectric_fresnel(std::cos(0.8f), 1.0f / 1.5f), 1.0f);
  EXPECT_LT(exact_dielectric_fresnel(std::cos(0.7f), 1.0f / 1.5f), 1.0f);
  // Grazing incidence reflects everything; matched media reflect nothing.
  EXPECT_EQ(exact_dielectric_fresnel(0.0f, 1.5f), 1.0f);
  EXPECT_EQ(exact_dielectric_fresnel(0.7f, 1.0f), 0.0f);
}

TEST(Whitted, GlassSurfaceReflectsFourPercentAtNormalIncidence) {
  Scene scene;
  const glm::vec3 e(10.0f, 20.0f, 30.0f);
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::glass_material(1.5f)));
  add_square_z(scene, 0, 0, 3, 10, false, add_material(scene, test::emissive_material(e)));
  // The refracted ray leaves downwards into nothing: only the reflection is seen.
  expect_rel(radiance(scene, ray_from({0.1f, 0.2f, 1}, {0, 0, -1})), 0.04f * e, 1e-5f);
}

TEST(Whitted, RefractionFollowsSnell) {
  // A ray at 45 degrees enters glass (ior 1.5) at the origin; a thin emissive strip one unit
  // below lies where Snell's law sends it: x = tan(asin(sin 45 / 1.5)) = 0.5345.
  Scene scene;
  const glm::vec3 e(1.0f);
  Material glass = test::glass_material(1.5f);
  glass.thickness = 1.0f;  // KHR_materials_volume: only a volume boundary refracts
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, glass));
  const std::uint32_t strip = add_material(scene, test::emissive_material(e));
  const float x = std::tan(std::asin(std::sqrt(0.5f) / 1.5f));
  append_quad(scene, {x - 0.01f, -1, -1}, {x + 0.01f, -1, -1}, {x + 0.01f, 1, -1}, {x - 0.01f, 1, -1}, strip);
  const glm::vec3 dir = glm::normalize(glm::vec3(1, 0, -1));
  const float F = exact_dielectric_fresnel(std::sqrt(0.5f), 1.5f);
  expect_rel(radiance(scene, ray_from(-dir, dir)), (1.0f - F) * e, 1e-5f);
  // Moving the strip by 0.03 (a 1 degree error in the angle) loses it.
  Scene shifted = scene;
  for (int k = 0; k < 3; ++k)
    for (std::size_t i = 2; i < 4; ++i) shifted.triangles.x[k][i] += 0.03f;
  EXPECT_EQ(radiance(shifted, ray_from(-dir, dir)), glm::vec3(0.0f));
}

TEST(Whitted, GlassSlabConservesEnergy) {
  // Slab z in [-0.5, 0] with outward faces, equal emitters above and below: whatever splits
  // between reflection and transmission, lossless glass returns exactly the emission.
  Scene scene;
  const glm::vec3 e(3.0f);
  const std::uint32_t glass = add_material(scene, test::glass_material(1.5f));
  add_square_z(scene, 0, 0, 0, 20, true, glass);
  add_square_z(scene, 0, 0, -0.5f, 20, false, glass);
  const std::uint32_t light = add_material(scene, test::emissive_material(e));
  add_square_z(scene, 0, 0, 3, 50, false, light);
  add_square_z(scene, 0, 0, -3, 50, true, light);
  for (float angle : {0.0f, 0.5f, 1.0f, 1.4f}) {
    const glm::vec3 dir(std::sin(angle), 0.0f, -std::cos(angle));
    expect_rel(radiance(scene, ray_from(glm::vec3(0, 0, 0.5f) - dir, dir), 40), e, 1e-5f);
  }
}

TEST(Whitted, GlassSlabSplitsLikeTheAiryFormula) {
  // Only the emitter below: a two-interface slab at normal incidence transmits
  // T^2 / (1 - R^2) with R = 0.04, T = 0.96 (incoherent sum of internal reflections).
  Scene scene;
  const glm::vec3 e(1.0f);
  const std::uint32_t glass = add_material(scene, test::glass_material(1.5f));
  add_square_z(scene, 0, 0, 0, 20, true, glass);
  add_square_z(scene, 0, 0, -0.5f, 20, false, glass);
  add_square_z(scene, 0, 0, -3, 50, true, add_material(scene, test::emissive_material(e)));
  const float R = 0.04f, T = 0.96f;
  expect_rel(radiance(scene, ray_from({0.1f, 0.1f, 1}, {0, 0, -1}), 40), e * (T * T / (1 - R * R)), 1e-5f);
}

TEST(Whitted, CountsEveryRay) {
  LitFloor f;
  std::uint64_t rays = 0;
  radiance(f.scene, ray_from({0, 0, 5}, {0, 0, -1}), 8, 4, &rays);
  EXPECT_EQ(rays, 2u);  // camera ray + one shadow ray (no area lights)
  radiance(f.scene, ray_from({0, 0, 5}, {0, 0, 1}), 8, 4, &rays);
  EXPECT_EQ(rays, 1u);  // a miss
}

// Whitted shades what the path tracer shades (evaluate_shading): an emissive texture
// scales the emission, a base colour texture the diffuse reflection. (It used the
// material's factors alone before.)
TEST(Whitted, TexturesApplyAsInThePathTracer) {
  for (const bool emissive : {true, false}) {
    Scene scene;
    const int texture = test::add_one_texel_texture(scene, 128, 64, 32);  // sRGB
    Material m = test::diffuse_material(glm::vec3(1.0f));
    if (emissive) {
      m.emissive_factor = glm::vec3(2.0f);
      m.emissive_texture.texture = texture;
    } else {
      m.base_color_texture.texture = texture;
    }
    scene.materials.push_back(m);
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
    SceneBuilder builder(scene, "quad");
    for (const auto& tri : {std::array<glm::vec3, 3>{a, b, c}, std::array<glm::vec3, 3>{a, c, d}}) {
      const glm::vec2 uv[3] = {{tri[0].x, tri[0].y}, {tri[1].x, tri[1].y}, {tri[2].x, tri[2].y}};
      CornerAttributes attribs;
      attribs.texcoords = uv;
      builder.add_triangle(tri.data(), 0, 0, attribs);
    }
    if (!emissive) {  // lit by a point light straight above
      PunctualLight light;
      light.type = LightType::Point;
      light.position = {0.5f, 0.5f, 1.0f};
      light.intensity = 3.0f;
      scene.lights.push_back(light);
    }
    const Ray ray = test::ray_from({0.5f, 0.5f, 2.0f}, {0, 0, -1});
    const BruteForce accel(scene.triangles);
    const ShadingInputs si = evaluate_shading(scene, ray, accel.intersect(ray));
    const glm::vec3 expected = emissive ? si.emission : si.base_color / 3.14159265f * 3.0f;
    ASSERT_LT(expected.z, expected.x * 0.5f) << "the texture must tint the result";
    const glm::vec3 L = radiance(scene, ray);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(L[k], expected[k], 1e-4f * expected.x) << (emissive ? "emission" : "diffuse") << k;
  }
}

// Area light samples carry the emitter's texture (sample_area_light, shared with the path
// tracer): a floor under a light whose texture is orange comes out orange, in the texel's
// proportions. (Whitted used the emissive factor alone for its light samples before.)
TEST(Whitted, AreaLightSamplesCarryTheEmissiveTexture) {
  Scene scene;
  add_square_z(scene, 0, 0, 0, 10, true, add_material(scene, test::diffuse_material(glm::vec3(0.5f))));
  Material light = test::emissive_material(glm::vec3(4.0f));
  light.emissive_texture.texture = test::add_one_texel_texture(scene, 200, 100, 50);
  add_square_z(scene, 0, 0, 1, 0.5f, false, add_material(scene, light));
  const glm::vec3 L = radiance(scene, ray_from({0.05f, 0.02f, 0.5f}, {0, 0, -1}), 8, 64);
  const glm::vec3 texel(srgb8_to_linear(200), srgb8_to_linear(100), srgb8_to_linear(50));
  ASSERT_GT(L.x, 0.0f);
  EXPECT_NEAR(L.y / L.x, texel.y / texel.x, 1e-4f);
  EXPECT_NEAR(L.z / L.x, texel.z / texel.x, 1e-4f);
}

}  // namespace
}  // namespace lancer
