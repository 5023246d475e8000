// LightEmission: the mean photon power is the scene's emitted power, light by light, and
// photons leave their emitting side without hitting their own light. (The irradiance the
// photons deliver: light_emission_irradiance_test.cpp.) Every comparison allows 4.5 standard
// errors plus float rounding; the seeds are fixed, so the tests are deterministic.
#include "render/light_emission.h"

#include <array>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "light_emission_test_support.h"
#include "render/color.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"

namespace lancer::test {
namespace {

// ---- 1. The mean photon power is the emitted power. ---------------------------------------

TEST(LightEmissionPower, OneSidedQuadEmitsPiTimesAreaTimesRadiance) {
  Scene scene;
  const glm::vec3 le(1.0f, 0.5f, 0.25f);
  add_square_z(scene, 0, 0, 1, 0.75f, false, add_material(scene, test::emissive_material(le, 2.0f)));
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  ASSERT_EQ(emission.size(), 1u);
  const glm::dvec3 expected = kPi * 2.25 * 2.0 * glm::dvec3(le);
  expect_agrees(mean_power(emission, 4096), expected, glm::dvec3(0.0), "one-sided quad");
  EXPECT_NEAR(emission.total_power(), kPi * 2.25 * 2.0 * luminance(le), 1e-5);
}

TEST(LightEmissionPower, TwoSidedQuadEmitsTwice) {
  Scene scene;
  Material m = test::emissive_material(glm::vec3(3.0f, 2.0f, 1.0f));
  m.double_sided = true;
  add_square_z(scene, 0, 0, 1, 0.5f, true, add_material(scene, m));
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  expect_agrees(mean_power(emission, 4096), 2.0 * kPi * glm::dvec3(3.0, 2.0, 1.0), glm::dvec3(0.0), "two-sided quad");
}

// Three quarters of the square emit, at coverage 1/2: the photons read the texture at their
// point, whatever AreaLights' grid estimate of the power made of the pick.
TEST(LightEmissionPower, TexturedEmitterCarriesTextureAndCoverage) {
  Scene scene;
  add_uv_square(scene, textured_emitter(scene));
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  expect_agrees(mean_power(emission, 200000), glm::dvec3(kPi * 0.75 * 0.5), glm::dvec3(0.0), "textured emitter");
}

TEST(LightEmissionPower, PointLightEmitsFourPiIntensity) {
  Scene scene;
  PunctualLight l = punctual(LightType::Point, {1.0f, 0.5f, 0.25f}, 3.0f);
  l.position = {1, 2, 3};
  l.range = 7.0f;
  scene.lights.push_back(l);
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  expect_agrees(mean_power(emission, 1024), 4.0 * kPi * 3.0 * glm::dvec3(1.0, 0.5, 0.25), glm::dvec3(0.0), "point");
  const EmittedPhoton p = shoot(emission, 0);
  EXPECT_EQ(p.ray.org, l.position);
  EXPECT_EQ(p.range, 7.0f);
  EXPECT_NEAR(glm::length(p.ray.dir), 1.0f, 1e-6f);
}

// The spot's power: illuminate()'s intensity at unit distance, integrated over the sphere
// (midpoint rule in the angle from the axis, fine enough for the falloff's kinks).
TEST(LightEmissionPower, SpotLightEmitsItsFalloffIntegratedOverTheSphere) {
  // A wide ramp, a narrow cone, a hard edge (inner = outer) and a hemisphere.
  const std::array<float, 2> cones[] = {{0.3f, 0.6f}, {0.0f, 0.2f}, {0.5f, 0.5f}, {0.1f, 1.5707963f}};
  for (const auto& [inner, outer] : cones) {
    Scene scene;
    PunctualLight l = punctual(LightType::Spot, {0.5f, 1.0f, 2.0f}, 4.0f);
    l.position = {0.5f, -1.0f, 2.0f};
    l.direction = glm::vec3(1.0f, -2.0f, 0.5f);  // not unit: illuminate() normalises it
    l.inner_cone = inner;
    l.outer_cone = outer;
    scene.lights.push_back(l);
    const glm::vec3 axis = glm::normalize(l.direction);
    const glm::vec3 across = glm::normalize(glm::cross(axis, glm::vec3(0, 0, 1)));
    constexpr int kSteps = 40000;
    glm::dvec3 expected(0.0);
    for (int k = 0; k < kSteps; ++k) {
      const double theta = kPi * (k + 0.5) / kSteps;
      const glm::vec3 dir = float(std::cos(theta)) * axis + float(std::sin(theta)) * across;
      expected += glm::dvec3(illuminate(l, l.position + dir).irradiance) * (2.0 * kPi * std::sin(theta) * kPi / kSteps);
    }
    const AreaLights lights(scene);
    const LightEmission emission(scene, lights, nullptr);
    ASSERT_EQ(emission.size(), 1u);
    EXPECT_NEAR(emission.total_power(), luminance(glm::vec3(expected)), 2e-3 * luminance(glm::vec3(expected)));
    expect_agrees(mean_power(emission, 100000), expected, 1e-4 * expected,
                  "spot " + std::to_string(inner) + " " + std::to_string(outer));
  }
}

TEST(LightEmissionPower, DirectionalLightEmitsIrradianceTimesTheDisc) {
  Scene scene;
  add_floor(scene);
  add_square_z(scene, 1.0f, 0.5f, 1.5f, 0.25f, true, 0);  // some height
  PunctualLight l = punctual(LightType::Directional, {1.0f, 0.8f, 0.6f}, 2.0f);
  l.direction = {0.3f, -0.2f, -1.0f};
  scene.lights.push_back(l);
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  // R covers the scene: the disc's photons start in front of every vertex, and R is at
  // most a little more than the bounding sphere's.
  const double r = emission.scene_radius();
  const Bounds3 b = scene.bounds();
  EXPECT_LE(r, 0.5 * glm::length(b.hi - b.lo) * 1.01);
  EXPECT_EQ(emission.scene_center(), b.center());
  // The origins are uniform on the disc: rho^2 / R^2 is uniform in [0, 1).
  const glm::vec3 dir = glm::normalize(l.direction);
  MeanRgb rho2;  // channel 0 only
  for (std::uint32_t i = 0; i < 100000; ++i) {
    const EmittedPhoton p = shoot(emission, i);
    ASSERT_TRUE(p.valid);
    ASSERT_NEAR(glm::length(p.ray.dir - dir), 0.0f, 1e-6f);
    for (std::size_t t = 0; t < scene.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k) ASSERT_GT(glm::dot(scene.triangles.vertex(t, k) - p.ray.org, dir), 0.0f);
    const glm::vec3 offset = p.ray.org - (emission.scene_center() - float(r) * dir);
    ASSERT_NEAR(glm::dot(offset, dir), 0.0f, 1e-5f * r);
    ASSERT_LE(glm::length(offset), r * 1.0001);
    rho2.add(glm::dvec3(glm::dot(offset, offset) / (r * r)));
  }
  EXPECT_NEAR(rho2.mean().x, 0.5, 4.5 * rho2.error().x);
  expect_agrees(mean_power(emission, 1024), 2.0 * kPi * r * r * glm::dvec3(1.0, 0.8, 0.6), glm::dvec3(0.0),
                "directional");
}

TEST(LightEmissionPower, EnvironmentEmitsItsRadianceIntegralTimesTheDisc) {
  Scene scene;
  add_floor(scene);
  const AreaLights lights(scene);
  const Environment constant(glm::vec3(0.2f, 0.4f, 0.8f));
  const LightEmission uniform(scene, lights, &constant);
  const double disc = kPi * uniform.scene_radius() * uniform.scene_radius();
  expect_agrees(mean_power(uniform, 4096), disc * 4.0 * kPi * glm::dvec3(0.2, 0.4, 0.8), glm::dvec3(0.0),
                "constant");

  const Environment map = small_map();
  const LightEmission mapped(scene, lights, &map);
  const glm::dvec3 integral = integrate_environment(map, [](const glm::vec3&) { return 1.0; });
  const double luminance_integral = disc * luminance(glm::vec3(integral));
  EXPECT_NEAR(mapped.total_power(), luminance_integral, 1e-4 * luminance_integral);
  expect_agrees(mean_power(mapped, 200000), disc * integral, 1e-5 * disc * integral, "map");
}

// Lights that emit nothing are never picked, and a scene of nothing but them is empty.
TEST(LightEmissionPower, DegenerateLightsAreNotPicked) {
  Scene scene;
  scene.lights.push_back(punctual(LightType::Point, glm::vec3(1.0f), 0.0f));
  PunctualLight closed = punctual(LightType::Spot, glm::vec3(1.0f), 5.0f);
  closed.outer_cone = 0.0f;
  scene.lights.push_back(closed);
  PunctualLight aimless = punctual(LightType::Spot, glm::vec3(1.0f), 5.0f);
  aimless.direction = glm::vec3(0.0f);
  scene.lights.push_back(aimless);
  scene.lights.push_back(punctual(LightType::Directional, glm::vec3(1.0f), 5.0f));  // no scene to light
  const Environment black(glm::vec3(0.0f));
  const AreaLights lights(scene);
  EXPECT_TRUE(LightEmission(scene, lights, &black).empty());
  const Environment sky(glm::vec3(1.0f));
  EXPECT_TRUE(LightEmission(scene, lights, &sky).empty()) << "no bounds, no disc";

  PunctualLight point = punctual(LightType::Point, glm::vec3(1.0f), 2.0f);
  point.position = {0, 0, 1};
  scene.lights.push_back(point);
  const LightEmission emission(scene, lights, &black);
  ASSERT_EQ(emission.size(), 1u);
  for (std::uint32_t i = 0; i < 1000; ++i) {
    const EmittedPhoton p = shoot(emission, i);
    ASSERT_TRUE(p.valid);
    EXPECT_EQ(p.ray.org, point.position);
  }
}


// ---- 3. Photons leave their light's emitting side. ----------------------------------------

// A tilted quad far from the origin, where the float grid is coarse: every photon leaves an
// emitting side and cannot hit the light itself (the brute-force oracle, with the watertight
// test the kd-tree reproduces). Directions are cosine-distributed about the side's normal
// (mean cosine 2/3), and a two-sided light sends half of its photons each way.
TEST(LightEmissionDirections, PhotonsLeaveTheEmittingSideAndMissTheirLight) {
  for (const bool two_sided : {false, true}) {
    Scene scene;
    Material m = emissive_material(glm::vec3(1.0f));
    m.double_sided = two_sided;
    const glm::vec3 o(1000.5f, -480.25f, 300.125f), e1(1.0f, 0.3f, -0.2f), e2(-0.1f, 0.4f, 0.9f);
    append_quad(scene, o, o + e1, o + e1 + e2, o + e2, add_material(scene, m));
    const glm::vec3 n = glm::normalize(glm::cross(e1, e2));
    const AreaLights lights(scene);
    const LightEmission emission(scene, lights, nullptr);
    const BruteForce oracle(scene.triangles);
    constexpr int kPhotons = 100000;
    MeanRgb cosine, front;  // channel 0 only
    int hits = 0;
    for (int i = 0; i < kPhotons; ++i) {
      const EmittedPhoton p = shoot(emission, static_cast<std::uint32_t>(i));
      ASSERT_TRUE(p.valid) << "photon " << i;
      ASSERT_GT(luminance(p.power), 0.0f);
      const float c = glm::dot(p.ray.dir, n);
      if (!two_sided) {
        ASSERT_GT(c, 0.0f) << "photon " << i << " leaves the back";
      }
      ASSERT_NE(c, 0.0f);
      cosine.add(glm::dvec3(std::abs(c)));
      front.add(glm::dvec3(c > 0.0f ? 1.0 : 0.0));
      if (oracle.intersect(p.ray).valid()) ++hits;
    }
    EXPECT_EQ(hits, 0) << "photons that hit their own light, two-sided " << two_sided;
    EXPECT_NEAR(cosine.mean().x, 2.0 / 3.0, 4.5 * cosine.error().x);
    EXPECT_NEAR(front.mean().x, two_sided ? 0.5 : 1.0, 4.5 * front.error().x + 1e-12);
  }
}

}  // namespace
}  // namespace lancer::test
