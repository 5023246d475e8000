// LightEmission against next-event estimation: the flux photons carry through a small
// receiving disc, over its area, is the irradiance the path tracer's light sampling gives
// there (illuminate() for punctual lights, sample_area_light for emissive triangles, the
// environment's radiance integrated over the disc's hemisphere). Receivers are intersected
// analytically, so no accelerator plays a part; the photon side applies the range window as
// the photon tracer will, at the distance to the receiver.
#include "render/light_emission.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "light_emission_test_support.h"
#include "render/bsdf_base.h"
#include "render/light_sampling.h"
#include "render/lights.h"
#include "render_test_scenes.h"

namespace lancer::test {
namespace {

// A disc lit from the side its normal points to.
struct Receiver {
  glm::vec3 center{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // any length
  float radius = 0.1f;
};

std::string describe(const Receiver& r) {
  return "receiver at (" + std::to_string(r.center.x) + ", " + std::to_string(r.center.y) + ", " +
         std::to_string(r.center.z) + ") facing (" + std::to_string(r.normal.x) + ", " + std::to_string(r.normal.y) +
         ", " + std::to_string(r.normal.z) + ")";
}

// The photon's flux through the receiver's front side, over its area.
glm::dvec3 photon_irradiance(const EmittedPhoton& p, const Receiver& r) {
  const glm::vec3 n = glm::normalize(r.normal);
  const float dn = glm::dot(p.ray.dir, n);
  if (!p.valid || !(dn < 0.0f)) return glm::dvec3(0.0);
  const float t = glm::dot(r.center - p.ray.org, n) / dn;
  if (!(t > 0.0f) || glm::length(p.ray.org + t * p.ray.dir - r.center) >= r.radius) return glm::dvec3(0.0);
  return glm::dvec3(p.power) * double(range_window(t, p.range)) / (kPi * r.radius * r.radius);
}

// Per receiver, the photons' irradiance estimate from `count` photons.
std::vector<MeanRgb> photon_estimates(const LightEmission& emission, const std::vector<Receiver>& receivers,
                                      int count) {
  std::vector<MeanRgb> out(receivers.size());
  for (int i = 0; i < count; ++i) {
    const EmittedPhoton p = shoot(emission, static_cast<std::uint32_t>(i));
    for (std::size_t k = 0; k < receivers.size(); ++k) out[k].add(photon_irradiance(p, receivers[k]));
  }
  return out;
}

// The mean of f over the disc: midpoints of 32 equal-area rings x 64 sectors.
template <typename F>
glm::dvec3 disc_average(const Receiver& r, F f) {
  const ShadingFrame frame = ShadingFrame::from_normal(glm::normalize(r.normal));
  constexpr int kRings = 32, kSectors = 64;
  glm::dvec3 sum(0.0);
  for (int k = 0; k < kRings; ++k)
    for (int j = 0; j < kSectors; ++j) {
      const float rho = r.radius * std::sqrt((k + 0.5f) / kRings), phi = float(2.0 * kPi * (j + 0.5) / kSectors);
      sum += f(r.center + frame.to_world(glm::vec3(rho * std::cos(phi), rho * std::sin(phi), 0.0f)));
    }
  return sum / double(kRings * kSectors);
}

// Next-event estimation's irradiance on the receiver, averaged over it, with its standard
// error (non-zero for area lights only, estimated with `samples` light samples).
struct Expected {
  glm::dvec3 value{0.0}, error{0.0};
};

Expected expected_irradiance(const Scene& scene, const AreaLights& lights, const Environment* env,
                             const Receiver& r, int samples) {
  const glm::vec3 n = glm::normalize(r.normal);
  Expected e;
  for (const PunctualLight& light : scene.lights)
    e.value += disc_average(r, [&](const glm::vec3& x) {
      const PunctualIncidence in = illuminate(light, x);
      return glm::dvec3(in.irradiance) * double(std::max(0.0f, glm::dot(in.wi, n)));
    });
  if (!lights.empty()) {
    const ShadingFrame frame = ShadingFrame::from_normal(n);
    MeanRgb area;
    for (int i = 0; i < samples; ++i) {
      const PixelSampler s(static_cast<std::uint32_t>(i), 1, 0, kSeed);
      const float rho = r.radius * std::sqrt(s.get(0)), phi = float(2.0 * kPi) * s.get(1);
      const glm::vec3 x = r.center + frame.to_world(glm::vec3(rho * std::cos(phi), rho * std::sin(phi), 0.0f));
      const LightSample ls = sample_area_light(scene, lights, x, s.get(2), {s.get(3), s.get(4)});
      const float cos_x = glm::dot(ls.wi, n);
      area.add(ls.valid && cos_x > 0.0f ? glm::dvec3(ls.radiance) * double(cos_x / ls.pdf_solid_angle())
                                        : glm::dvec3(0.0));
    }
    e.value += area.mean();
    e.error = area.error();
  }
  if (env != nullptr) {
    const auto cosine = [&](const glm::vec3& dir) { return std::max(0.0, double(glm::dot(dir, n))); };
    e.value += integrate_environment(*env, cosine);
  }
  return e;
}

// Every receiver's photon estimate agrees with next-event estimation.
void expect_consistent(const Scene& scene, const AreaLights& lights, const Environment* env,
                       const std::vector<Receiver>& receivers, int photons, int light_samples = 0) {
  const LightEmission emission(scene, lights, env);
  const std::vector<MeanRgb> estimates = photon_estimates(emission, receivers, photons);
  for (std::size_t k = 0; k < receivers.size(); ++k) {
    const Expected e = expected_irradiance(scene, lights, env, receivers[k], light_samples);
    expect_agrees(estimates[k], e.value, e.error, describe(receivers[k]));
  }
}

// ---- 2. Photons deliver the irradiance next-event estimation sees. ------------------------

// A unit square 1 above the floor, facing down; one-sided, nothing reaches the receiver above
// it, and grazing and tilted receivers get their cosines.
TEST(LightEmissionIrradiance, AreaLightMatchesLightSampling) {
  for (const bool two_sided : {false, true}) {
    Scene scene;
    Material m = emissive_material(glm::vec3(2.0f, 1.0f, 0.5f));
    m.double_sided = two_sided;
    add_square_z(scene, 0, 0, 1, 0.5f, false, add_material(scene, m));
    const AreaLights lights(scene);
    const std::vector<Receiver> receivers = {{{0.0f, 0.0f, 0.0f}, {0, 0, 1}, 0.2f},
                                             {{0.7f, 0.3f, 0.3f}, {-0.6f, -0.2f, 1.0f}, 0.15f},
                                             {{1.2f, 0.0f, 0.8f}, {-1, 0, 0}, 0.15f},
                                             {{0.1f, -0.2f, 1.5f}, {0, 0, -1}, 0.2f}};
    SCOPED_TRACE(two_sided ? "two-sided" : "one-sided");
    expect_consistent(scene, lights, nullptr, receivers, 1000000, 200000);
  }
}

// The strip's left quarter is black and its coverage 1/2: above the black part, only light
// from the white part arrives, at a slant.
TEST(LightEmissionIrradiance, TexturedAreaLightMatchesLightSampling) {
  Scene scene;
  add_uv_square(scene, textured_emitter(scene));
  const AreaLights lights(scene);
  const std::vector<Receiver> receivers = {{{0.1f, 0.5f, 0.2f}, {0, 0, -1}, 0.08f},
                                           {{0.7f, 0.5f, 0.3f}, {0, 0, -1}, 0.15f},
                                           {{-0.3f, 0.4f, 0.4f}, {1, 0, -1}, 0.15f}};
  expect_consistent(scene, lights, nullptr, receivers, 1000000, 200000);
}

// A tilted spot with a finite range: receivers inside the inner cone, on the falloff's ramp
// (across and along the tilt), outside the outer cone, and one facing away.
TEST(LightEmissionIrradiance, SpotLightMatchesIlluminate) {
  Scene scene;
  PunctualLight l = punctual(LightType::Spot, {3.0f, 2.0f, 1.0f}, 2.0f);
  l.position = {0.0f, 0.0f, 2.0f};
  l.direction = {0.3f, 0.0f, -1.0f};
  l.inner_cone = 0.25f;
  l.outer_cone = 0.45f;
  l.range = 4.0f;
  scene.lights.push_back(l);
  const AreaLights lights(scene);
  const std::vector<Receiver> receivers = {{{0.6f, 0.0f, 0.0f}, {0, 0, 1}, 0.15f},
                                           {{1.45f, 0.0f, 0.0f}, {0, 0, 1}, 0.1f},
                                           {{-0.12f, 0.0f, 0.0f}, {0.5f, 0, 1}, 0.1f},
                                           {{0.6f, 0.7f, 0.0f}, {0, -0.3f, 1}, 0.1f},
                                           {{3.0f, 0.0f, 0.0f}, {0, 0, 1}, 0.2f},
                                           {{0.6f, 0.0f, 0.0f}, {0, 0, -1}, 0.15f}};
  expect_consistent(scene, lights, nullptr, receivers, 1000000);
}

// A dim point light beside a directional light that emits about 80 times its power (only
// about one photon in 80 is the point light's, and each must carry 80 times more), and two
// small emitters, whose share of u_pick must be stretched back over AreaLights' own pick.
TEST(LightEmissionIrradiance, LightsOfVeryDifferentPowerArePickedWithoutBias) {
  Scene scene;
  add_floor(scene);
  const std::uint32_t emitter = add_material(scene, emissive_material(glm::vec3(4.0f, 3.0f, 2.0f)));
  add_square_z(scene, -1.0f, -1.0f, 1.2f, 0.25f, false, emitter);
  add_square_z(scene, 1.0f, -1.0f, 1.2f, 0.25f, false, emitter);
  PunctualLight point = punctual(LightType::Point, {1.0f, 0.9f, 0.8f}, 0.05f);
  point.position = {0.0f, 0.0f, 0.5f};
  scene.lights.push_back(point);
  PunctualLight sun = punctual(LightType::Directional, {1.0f, 1.0f, 0.9f}, 2.0f);
  sun.direction = {0.2f, 0.1f, -1.0f};
  scene.lights.push_back(sun);
  const AreaLights lights(scene);
  const LightEmission emission(scene, lights, nullptr);
  ASSERT_EQ(emission.size(), 3u);
  EXPECT_LT(emission.pick_probability(1), 0.02) << "the point light";
  const std::vector<Receiver> receivers = {{{0.0f, 0.0f, 0.2f}, {0, 0, 1}, 0.1f},
                                           {{0.2f, 0.1f, 0.35f}, {-1, -0.5f, 0.2f}, 0.08f},
                                           {{1.0f, 1.0f, 0.3f}, {0, 0, 1}, 0.3f},
                                           {{1.0f, -1.0f, 0.5f}, {0, 0, 1}, 0.15f},
                                           {{-1.0f, -1.0f, 0.5f}, {0.3f, 0, 1}, 0.15f}};
  expect_consistent(scene, lights, nullptr, receivers, 3000000, 100000);
}

// A constant environment gives pi L whatever the orientation; a map, its radiance times the
// cosine integrated over the receiver's hemisphere.
TEST(LightEmissionIrradiance, EnvironmentMatchesItsRadianceOverTheHemisphere) {
  Scene scene;
  add_floor(scene);
  const AreaLights lights(scene);
  const std::vector<Receiver> receivers = {{{0.0f, 0.0f, 0.5f}, {0, 0, 1}, 0.4f},
                                           {{0.5f, -0.5f, 0.2f}, {1, 1, 0.5f}, 0.4f},
                                           {{-1.0f, 0.5f, 1.0f}, {0, -1, -0.3f}, 0.4f}};
  const Environment constant(glm::vec3(0.3f, 0.6f, 0.9f));
  expect_consistent(scene, lights, &constant, receivers, 1000000);
  const Environment map = small_map();
  expect_consistent(scene, lights, &map, receivers, 1000000);
}

}  // namespace
}  // namespace lancer::test
