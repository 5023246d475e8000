#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include "render/debug_integrators.h"
#include "render/lights.h"
#include "render/primary_block.h"
#include "render/sampler.h"
#include "render/tile_scheduler.h"
#include "render/whitted.h"

namespace lancer {

namespace {

void check_settings(const Scene& scene, const PinholeCamera& camera, const RenderSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("render settings: " + what); };
  if (s.width <= 0 || s.height <= 0) fail("image size must be positive");
  if (camera.width() != s.width || camera.height() != s.height)
    fail("camera is " + std::to_string(camera.width()) + "x" + std::to_string(camera.height()) + " but the image is " +
         std::to_string(s.width) + "x" + std::to_string(s.height));
  if (s.spp <= 0) fail("samples per pixel must be positive");
  if (s.max_depth < 0) fail("max depth must be >= 0");
  if (s.light_samples < 0) fail("light samples must be >= 0");
  if (s.threads < 0) fail("threads must be >= 0");
  if (s.tile_size <= 0) fail("tile size must be positive");
  if (s.mode != TraceMode::Packet && s.mode != TraceMode::Single) fail("unknown trace mode");
  if (scene.material_id.size() != scene.triangle_count() || scene.materials.empty())
    fail("scene " + scene.source + " has no material for some triangles");
}

}  // namespace

ImageRGB render_image(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                      const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress) {
  check_settings(scene, camera, settings);
  const auto start = std::chrono::steady_clock::now();

  const AreaLights area_lights(scene);
  const WhittedIntegrator whitted(scene, accel, area_lights, settings.max_depth, settings.light_samples);
  ImageRGB image(settings.width, settings.height);
  std::atomic<std::uint64_t> total_rays{0};
  std::atomic<std::uint64_t> total_primary_rays{0};
  std::atomic<std::chrono::steady_clock::rep> total_primary_ticks{0};  // summed over threads
  const float inv_spp = 1.0f / static_cast<float>(settings.spp);

  auto shade = [&](const Ray& ray, const Hit& hit, PixelSampler& sampler, std::uint64_t& rays) {
    return settings.integrator == IntegratorKind::Whitted
               ? whitted.radiance_from_hit(ray, hit, sampler, rays)
               : debug_radiance_from_hit(settings.integrator, scene, ray, hit);
  };

  auto render_tile = [&](const Tile& tile) {
    std::uint64_t rays = 0;  // per tile, added to the totals once
    std::uint64_t primary_rays = 0;
    std::chrono::steady_clock::duration primary_time{0};
    PrimaryBlock primary;
    std::array<glm::vec3, kBlockPixels> sum;
    for (const PixelBlock& block : make_blocks(tile)) {
      const int n = block.pixel_count();
      std::fill_n(sum.begin(), n, glm::vec3(0.0f));
      // Samples in order 0..spp-1 for every pixel, so each pixel's sum is added up in the
      // same order as when its samples are traced one ray at a time.
      for (int s = 0; s < settings.spp; ++s) {
        primary.generate(camera, block, s, settings.seed);
        primary_time += primary.trace(accel, settings.mode);
        primary_rays += static_cast<std::uint64_t>(n);
        for (int i = 0; i < n; ++i)
          sum[static_cast<std::size_t>(i)] += shade(primary.ray(i), primary.hit(i), primary.sampler(i), rays);
      }
      for (int i = 0; i < n; ++i) {
        const glm::vec3 mean = sum[static_cast<std::size_t>(i)] * inv_spp;
        image.set(block.x0 + i % block.width(), block.y0 + i / block.width(), mean);
      }
    }
    total_rays.fetch_add(rays + primary_rays, std::memory_order_relaxed);
    total_primary_rays.fetch_add(primary_rays, std::memory_order_relaxed);
    total_primary_ticks.fetch_add(primary_time.count(), std::memory_order_relaxed);
  };

  for_each_tile(make_tiles(settings.width, settings.height, settings.tile_size), settings.threads, render_tile,
                progress);

  stats.rays = total_rays.load();
  stats.primary_rays = total_primary_rays.load();
  stats.primary_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::duration(total_primary_ticks.load())).count();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace lancer
