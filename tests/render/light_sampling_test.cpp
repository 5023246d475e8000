// sample_area_light: the light sample every integrator uses for next-event estimation.
#include "render/light_sampling.h"

#include <cmath>

#include <gtest/gtest.h>

#include "render/color.h"
#include "render/shading_inputs.h"
#include "render/sobol_sampler.h"
#include "render_test_scenes.h"

namespace lancer {
namespace {

using test::add_material;
using test::add_square_z;

// A unit square light in the plane z = 1, centred above the origin, emitting downwards.
Scene square_light(const Material& m) {
  Scene scene;
  add_square_z(scene, 0, 0, 1, 0.5f, false, add_material(scene, m));
  return scene;
}

// E[1 / pdf_solid_angle] over the samples is the solid angle the light subtends: for a
// 1 x 1 square at height 1 above p, 4 asin(1 / 5) (the rectangle formula
// 4 asin(a b / sqrt((a^2 + 4 d^2)(b^2 + 4 d^2)))). Every sample from below is valid and
// looks up at the light's emitting side.
TEST(LightSampling, DensitiesIntegrateToTheSolidAngle) {
  const Scene scene = square_light(test::emissive_material(glm::vec3(1.0f)));
  const AreaLights lights(scene);
  const glm::vec3 p(0.0f);
  constexpr int kSamples = 4096;
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const SobolSampler sampler(0, 0, static_cast<std::uint32_t>(i), 7);
    const LightSample s = sample_area_light(scene, lights, p, sampler.get1(0), sampler.get2(1));
    ASSERT_TRUE(s.valid) << "sample " << i;
    EXPECT_GT(s.wi.z, 0.0f);
    EXPECT_NEAR(s.cos_l, s.wi.z, 1e-6f);
    EXPECT_NEAR(glm::length(s.point.point - p) * glm::length(s.point.point - p), s.dist2, 1e-5f);
    EXPECT_EQ(s.radiance, glm::vec3(1.0f));
    sum += 1.0 / s.pdf_solid_angle();
  }
  EXPECT_NEAR(sum / kSamples, 4.0 * std::asin(0.2), 2e-3);
}

// From above, p sees the light's back: nothing to add.
TEST(LightSampling, BehindTheEmittingSideIsInvalid) {
  const Scene scene = square_light(test::emissive_material(glm::vec3(1.0f)));
  const AreaLights lights(scene);
  for (int i = 0; i < 64; ++i) {
    const SobolSampler sampler(0, 0, static_cast<std::uint32_t>(i), 7);
    EXPECT_FALSE(sample_area_light(scene, lights, glm::vec3(0.2f, 0.1f, 2.0f), sampler.get1(0), sampler.get2(1)).valid);
  }
}

// An emissive texture scales the radiance the sample carries, as evaluate_shading sees the
// light's surface from p (glTF: emissiveFactor x strength x texture, the texture sRGB).
TEST(LightSampling, RadianceCarriesTheEmissiveTexture) {
  Material m = test::emissive_material(glm::vec3(2.0f), 1.5f);
  Scene scene = square_light(m);
  scene.materials[0].emissive_texture.texture = test::add_one_texel_texture(scene, 128, 64, 32);
  const AreaLights lights(scene);
  const glm::vec3 p(0.1f, -0.2f, 0.0f);
  const glm::vec3 texel(srgb8_to_linear(128), srgb8_to_linear(64), srgb8_to_linear(32));
  for (int i = 0; i < 16; ++i) {
    const SobolSampler sampler(0, 0, static_cast<std::uint32_t>(i), 7);
    const LightSample s = sample_area_light(scene, lights, p, sampler.get1(0), sampler.get2(1));
    ASSERT_TRUE(s.valid);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.radiance[c], 3.0f * texel[c], 1e-5f) << "channel " << c;
    Ray toward;
    toward.org = p;
    toward.dir = s.wi;
    const ShadingInputs si =
        evaluate_shading(scene, toward, Hit{std::sqrt(s.dist2), s.point.prim, s.point.b1, s.point.b2});
    EXPECT_EQ(s.radiance, si.emission);
  }
}

}  // namespace
}  // namespace lancer
