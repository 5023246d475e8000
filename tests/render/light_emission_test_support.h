// Helpers of the LightEmission tests: photons from fixed uniforms, means with their
// standard errors, and the emitters and environments the tests light scenes with.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/environment.h"
#include "render/light_emission.h"
#include "render/sampler.h"
#include "render/texture.h"
#include "render_test_scenes.h"
#include "scene/scene_builder.h"

namespace lancer::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr std::uint64_t kSeed = 20261203;

// Photon i of a test: counter-based uniforms, independent from photon to photon.
inline EmittedPhoton shoot(const LightEmission& emission, std::uint32_t i) {
  const PixelSampler s(i, 0, 0, kSeed);
  return emission.sample(s.get(0), {s.get(1), s.get(2)}, {s.get(3), s.get(4)});
}

// Mean and standard error of independent samples, per RGB channel.
class MeanRgb {
 public:
  void add(const glm::dvec3& x) {
    ++n_;
    sum_ += x;
    sum2_ += x * x;
  }
  glm::dvec3 mean() const { return sum_ / double(n_); }
  glm::dvec3 error() const {
    const glm::dvec3 m = mean();
    const glm::dvec3 variance = glm::max(glm::dvec3(0.0), sum2_ / double(n_) - m * m) * (double(n_) / double(n_ - 1));
    return glm::sqrt(variance / double(n_));
  }

 private:
  std::size_t n_ = 0;
  glm::dvec3 sum_{0.0}, sum2_{0.0};
};

// `estimate` agrees with `expected` (itself estimated, with standard error expected_error,
// or exact): within 4.5 standard errors of both, plus float rounding.
inline void expect_agrees(const MeanRgb& estimate, const glm::dvec3& expected, const glm::dvec3& expected_error,
                          const std::string& what) {
  const glm::dvec3 m = estimate.mean(), e = estimate.error();
  for (int c = 0; c < 3; ++c) {
    const double tolerance = 4.5 * std::hypot(e[c], expected_error[c]) + 1e-5 * std::abs(expected[c]) + 1e-9;
    EXPECT_NEAR(m[c], expected[c], tolerance) << what << ", channel " << c << " (standard error " << e[c] << ")";
  }
}

// The photons' power over `count` photons (an invalid one counts as 0), all finite.
inline MeanRgb mean_power(const LightEmission& emission, int count) {
  MeanRgb power;
  for (int i = 0; i < count; ++i) {
    const EmittedPhoton p = shoot(emission, static_cast<std::uint32_t>(i));
    EXPECT_TRUE(std::isfinite(p.power.x + p.power.y + p.power.z));
    power.add(p.valid ? glm::dvec3(p.power) : glm::dvec3(0.0));
  }
  return power;
}

// A non-emissive floor, [-2, 2]^2 at z = 0: the bounds distant light enters.
inline void add_floor(Scene& scene) {
  add_square_z(scene, 0, 0, 0, 2.0f, true, add_material(scene, diffuse_material(glm::vec3(0.5f))));
}

// A 64 x 1 RGB strip, nearest-filtered: the left `black` texels black, the rest white.
inline int add_strip(Scene& scene, int black) {
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

// The unit square [0, 1]^2 at z = 0 emitting `m` upwards, with u = x for m's textures.
inline void add_uv_square(Scene& scene, const Material& m) {
  const std::uint32_t id = add_material(scene, m);
  SceneBuilder builder(scene, "emitter");
  const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (const auto& t : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
    const glm::vec3 corners[3] = {p[t[0]], p[t[1]], p[t[2]]};
    glm::vec2 uvs[3];
    for (int k = 0; k < 3; ++k) uvs[k] = glm::vec2(corners[k].x, corners[k].y);
    CornerAttributes attribs;
    attribs.texcoords = uvs;
    builder.add_triangle(corners, id, 0, attribs);
  }
}

// Emits (1, 1, 1) x strip texture (the left quarter black) x coverage 1/2 (BLEND).
inline Material textured_emitter(Scene& scene) {
  Material m = emissive_material(glm::vec3(1.0f));
  m.emissive_texture.texture = add_strip(scene, 16);
  m.alpha_mode = AlphaMode::Blend;
  m.base_color.a = 0.5f;
  return m;
}

inline PunctualLight punctual(LightType type, const glm::vec3& color, float intensity) {
  PunctualLight l;
  l.type = type;
  l.color = color;
  l.intensity = intensity;
  return l;
}

// A small map with smooth variation, a hot pixel and a black one.
inline Environment small_map() {
  ImageRGB image(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      image.set(x, y, glm::vec3(0.1f * float(1 + x), 0.2f * float(1 + y), 0.05f * float((x * y) % 5)));
  image.set(5, 2, glm::vec3(40.0f, 30.0f, 20.0f));
  image.set(9, 6, glm::vec3(0.0f));
  return Environment(std::move(image), 2.0f, "small map");
}

// The integral over the sphere of the environment's radiance times weight(direction
// toward it), on a grid of 32 x 32 cells per pixel with their exact solid angles.
template <typename Weight>
inline glm::dvec3 integrate_environment(const Environment& env, Weight weight) {
  const int w = env.is_constant() ? 64 : env.image().width * 32, h = env.is_constant() ? 64 : env.image().height * 32;
  glm::dvec3 sum(0.0);
  for (int y = 0; y < h; ++y) {
    const double solid_angle = 2.0 * kPi / w * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
    for (int x = 0; x < w; ++x) {
      const glm::vec3 dir = equirect_direction((x + 0.5) / w, (y + 0.5) / h);
      sum += glm::dvec3(env.radiance(dir)) * (weight(dir) * solid_angle);
    }
  }
  return sum;
}

}  // namespace lancer::test
