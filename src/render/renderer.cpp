#include "render/renderer.h"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>

#include "render/debug_integrators.h"
#include "render/lights.h"
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
  const float inv_spp = 1.0f / static_cast<float>(settings.spp);

  auto render_tile = [&](const Tile& tile) {
    std::uint64_t rays = 0;  // per tile, added to the total once
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        glm::vec3 sum(0.0f);
        for (int s = 0; s < settings.spp; ++s) {
          PixelSampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                               static_cast<std::uint32_t>(s), settings.seed);
          // Jitter over the pixel's area; a box filter averages the samples.
          const float u = sampler.next();
          const float v = sampler.next();
          const Ray ray = camera.generate(static_cast<float>(x) + u, static_cast<float>(y) + v);
          sum += settings.integrator == IntegratorKind::Whitted
                     ? whitted.radiance(ray, sampler, rays)
                     : debug_radiance(settings.integrator, scene, accel, ray, rays);
        }
        image.set(x, y, sum * inv_spp);
      }
    }
    total_rays.fetch_add(rays, std::memory_order_relaxed);
  };

  for_each_tile(make_tiles(settings.width, settings.height, settings.tile_size), settings.threads, render_tile,
                progress);

  stats.rays = total_rays.load();
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace lancer
