// What the photon mappers' tests share (sppm_test.cpp, caustic_map_test.cpp): a caustic in
// closed form, and the statistics of an image's block means over independent seeds.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "render/bsdf.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render_test_scenes.h"
#include "scene/procedural.h"
#include "scene/scene.h"

namespace lancer::test {

// A Lambertian floor (z = 0, albedo rho) under a thin-walled glass pane (z = 0.5, ior 1.5,
// transmission 1, smooth), lit only by a spot light straight above at height 2 whose full-
// intensity cone covers the view. The camera sits between pane and floor, looking down. The
// light reaches the floor only through the pane: next-event estimation finds it blocked and
// a BSDF-sampled path can never hit a point light, so the path tracer renders the floor black,
// while the floor's radiance is rho / pi * I cos(theta) / d^2 * T(theta), T the pane's
// transmittance at the angle of incidence (1 - F for a thin wall).
// Light the floor sends up and the pane mirrors back adds rho * F * (the pane's form factor,
// about 1/2) ~ 0.4 % with rho = 0.2: below the tolerance, and the only thing left out.
struct PaneCaustic {
  static constexpr float kRho = 0.2f, kIntensity = 10.0f, kLightHeight = 2.0f, kPaneHeight = 0.5f;
  Scene scene;
  std::uint32_t glass = 0;

  PaneCaustic() {
    const std::uint32_t floor = add_material(scene, diffuse_material(glm::vec3(kRho)));
    glass = add_material(scene, glass_material(1.5f));
    add_square_z(scene, 0.0f, 0.0f, 0.0f, 3.0f, true, floor);
    add_square_z(scene, 0.0f, 0.0f, kPaneHeight, 0.6f, true, glass);
    PunctualLight spot;
    spot.type = LightType::Spot;
    spot.position = glm::vec3(0.0f, 0.0f, kLightHeight);
    spot.direction = glm::vec3(0.0f, 0.0f, -1.0f);
    spot.intensity = kIntensity;
    spot.inner_cone = 0.2f;  // the view spans at most 0.1 rad seen from the light
    spot.outer_cone = 0.25f;
    scene.lights.push_back(spot);
  }

  // The pane's transmittance towards the light from a floor point seeing it along `to_light`.
  float transmittance(const glm::vec3& to_light) const {
    const Material& m = scene.materials[glass];
    BsdfInputs in{glm::vec3(1.0f), m.metallic, m.roughness, m.ior, 1.0f, glm::vec3(1.0f), 1.0f, true};
    const Bsdf bsdf(in, ShadingFrame::from_normal(glm::vec3(0.0f, 0.0f, 1.0f)), true);
    // Transmission is chosen for u_split at the top of [0, 1).
    const std::optional<BsdfSample> s = bsdf.sample(-to_light, 0.999999f, glm::vec2(0.5f));
    EXPECT_TRUE(s && s->delta && s->transmitted);
    return s ? s->weight.x * s->pdf : 0.0f;
  }

  double expected_radiance(const glm::vec3& x) const {
    const glm::vec3 to_light = glm::vec3(0.0f, 0.0f, kLightHeight) - x;
    const float d = glm::length(to_light);
    const double cos_theta = to_light.z / d;
    return kRho / std::numbers::pi * kIntensity * cos_theta / (double(d) * d) * transmittance(to_light / d);
  }
};

// A floor (Lambertian unless given) lit by an area light (facing down) through a thin glass
// pane and by way of a vertical mirror; some light goes mirror then pane. Seen from above
// (camera()): the floor directly and through the pane, the mirror, the light. The light is
// large, so the path tracer alone finds every caustic by BSDF sampling: the reference the
// caustic estimators (photon map, SPPM, light tracing) are held to.
struct GlassAndMirror {
  Scene scene;
  explicit GlassAndMirror(const Material& floor_material = diffuse_material(glm::vec3(0.6f, 0.5f, 0.4f))) {
    const std::uint32_t floor = add_material(scene, floor_material);
    const std::uint32_t glass = add_material(scene, glass_material(1.5f));
    const std::uint32_t mirror = add_material(scene, mirror_material(glm::vec3(0.9f)));
    const std::uint32_t light = add_material(scene, emissive_material(glm::vec3(2.0f)));
    add_square_z(scene, 0.0f, 0.0f, 0.0f, 1.0f, true, floor);
    add_square_z(scene, 0.25f, 0.0f, 0.4f, 0.3f, true, glass);
    // The mirror: x = -0.5, y in [-0.5, 0.5], z in [0, 0.7], facing +x.
    append_quad(scene, glm::vec3(-0.5f, -0.5f, 0.0f), glm::vec3(-0.5f, 0.5f, 0.0f), glm::vec3(-0.5f, 0.5f, 0.7f),
                glm::vec3(-0.5f, -0.5f, 0.7f), mirror);
    add_square_z(scene, 0.0f, 0.0f, 1.0f, 0.3f, false, light);
  }
  static PinholeCamera camera(int size) {
    return PinholeCamera::look_at(glm::vec3(0.3f, -1.1f, 1.5f), glm::vec3(0.0f, 0.0f, 0.1f),
                                  glm::vec3(0.0f, 0.0f, 1.0f), 1.0f, size, size);
  }
};

// Settings of a square render of `size` pixels at `spp` with `kind`, on two threads.
inline RenderSettings caustic_settings(IntegratorKind kind, int size, int spp) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = spp;
  s.integrator = kind;
  s.threads = 2;
  return s;
}

// Block means of an image: kBlocks x kBlocks blocks, channel by channel.
inline constexpr int kBlocks = 4;
inline std::vector<double> block_means(const ImageRGB& image) {
  std::vector<double> m(kBlocks * kBlocks * 3, 0.0);
  const int bw = image.width / kBlocks, bh = image.height / kBlocks;
  for (int y = 0; y < kBlocks * bh; ++y)
    for (int x = 0; x < kBlocks * bw; ++x)
      for (int ch = 0; ch < 3; ++ch)
        m[(std::size_t(y / bh) * kBlocks + std::size_t(x / bw)) * 3 + std::size_t(ch)] +=
            image.rgb[3 * (std::size_t(y) * image.width + std::size_t(x)) + std::size_t(ch)] / double(bw * bh);
  return m;
}

// Over independent seeds: the mean of each block mean and the standard error of that mean.
struct SeedStats {
  std::vector<double> mean, stderr_;
};
template <class Render>
SeedStats over_seeds(int seeds, Render render) {
  std::vector<std::vector<double>> runs;
  for (int k = 0; k < seeds; ++k) runs.push_back(block_means(render(std::uint64_t(1000 + k))));
  SeedStats out;
  const std::size_t n = runs[0].size();
  out.mean.assign(n, 0.0);
  out.stderr_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double s = 0.0, s2 = 0.0;
    for (const auto& r : runs) s += r[i], s2 += r[i] * r[i];
    const double mean = s / seeds;
    const double var = std::max(0.0, (s2 - seeds * mean * mean) / (seeds - 1));
    out.mean[i] = mean;
    out.stderr_[i] = std::sqrt(var / seeds);
  }
  return out;
}

// Expects `other`'s block means within 5 combined standard errors of `reference`'s, each
// failure labelled with `what`; returns how many resolve a difference of `resolution` (a
// mean above 0.01 whose tolerance is below that fraction of it), so a test can require
// that it could see one.
inline int expect_same_block_means(const SeedStats& reference, const SeedStats& other, const std::string& what,
                                   double resolution = 0.05) {
  int resolved = 0;
  for (std::size_t i = 0; i < reference.mean.size(); ++i) {
    const double tolerance = 5.0 * std::hypot(reference.stderr_[i], other.stderr_[i]);
    EXPECT_NEAR(other.mean[i], reference.mean[i], tolerance) << what << " block " << i / 3 << " channel " << i % 3;
    resolved += reference.mean[i] > 0.01 && tolerance < resolution * reference.mean[i];
  }
  return resolved;
}

inline bool bitwise_equal(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// The render of `settings` (threads 1, tile 16, packets) and the same with 2 and 3 threads,
// odd tiles and single rays, all bit for bit: photons are traced in fixed chunks and
// gathered in a fixed order. Returns the first image for the caller's own checks.
inline ImageRGB expect_bit_identical_across_threads_tiles_and_modes(const Scene& scene, const Accelerator& accel,
                                                                    const PinholeCamera& camera, RenderSettings s) {
  auto render = [&](int threads, int tile, TraceMode mode) {
    s.threads = threads;
    s.tile_size = tile;
    s.mode = mode;
    RenderStats stats;
    return render_image(scene, accel, camera, s, stats);
  };
  const ImageRGB one = render(1, 16, TraceMode::Packet);
  EXPECT_TRUE(bitwise_equal(one, render(2, 16, TraceMode::Packet)));
  EXPECT_TRUE(bitwise_equal(one, render(3, 5, TraceMode::Packet)));
  EXPECT_TRUE(bitwise_equal(one, render(2, 16, TraceMode::Single)));
  return one;
}

}  // namespace lancer::test
