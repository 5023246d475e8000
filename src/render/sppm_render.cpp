#include "render/sppm_render.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/enumerable_thread_specific.h>

#include "render/camera_emission.h"
#include "render/light_emission.h"
#include "render/lights.h"
#include "render/pixel_filter.h"
#include "render/photon_walk.h"
#include "render/primary_block.h"
#include "render/sppm.h"
#include "render/tile_scheduler.h"
#include "simd/out_of_memory.h"
#include "simd/process_memory.h"

namespace lancer {

namespace {

// Hachisuka & Jensen's alpha: the fraction of new photons a visible point keeps.
constexpr double kAlpha = 2.0 / 3.0;
constexpr double kPi = 3.14159265358979323846;

// What a pixel keeps from iteration to iteration.
struct PixelStats {
  glm::dvec3 direct{0.0};  // sum over iterations of what the camera paths found without photons
  glm::dvec3 tau{0.0};     // the flux of the photons kept, times the visible points' throughput
  double n = 0.0;          // photons kept (N)
  float radius = 0.0f;     // 0 until the pixel's first visible point
};

}  // namespace

ImageRGB render_sppm(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                     const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress,
                     const RenderControl& control) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool timed = control.time_limit_s > 0.0;
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(timed ? control.time_limit_s : 0.0));
  auto must_stop = [&] {
    return (control.stop && control.stop->load(std::memory_order_relaxed) != 0) || (timed && Clock::now() >= deadline);
  };

  const std::size_t pixels = static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height);
  const std::int64_t photons_per_iteration =
      settings.photons > 0 ? settings.photons
                           : std::min<std::int64_t>(static_cast<std::int64_t>(pixels), kMaxDefaultPhotons);
  const auto photon_count = static_cast<std::size_t>(photons_per_iteration);

  const AreaLights area_lights(scene);
  const LightEmission emission(scene, area_lights, settings.environment);
  const SppmIntegrator sppm(scene, accel, area_lights, emission, settings.environment, settings.max_depth,
                            settings.light_samples);
  const PixelFilter filter =
      settings.filter == PixelFilterType::Gaussian ? PixelFilter::gaussian() : PixelFilter::box();
  // A pixel's footprint per unit of distance (perspective), or in scene units (orthographic).
  const float pixel_footprint = 2.0f * glm::length(camera.y_axis()) / static_cast<float>(settings.height);
  auto initial_radius = [&](float distance) {
    if (settings.sppm_radius > 0.0f) return settings.sppm_radius;
    const float r = kSppmRadiusPixels * pixel_footprint * (camera.orthographic() ? 1.0f : distance);
    return r > 0.0f && std::isfinite(r) ? r : 0.0f;
  };

  // What every pixel holds for the whole render (136 bytes: 2^28 pixels would need 36 GiB),
  // refused before anything is allocated where the machine cannot hold it: the vectors would
  // be granted by the kernel's overcommit and the process killed while filling them.
  const double per_pixel = double(sizeof(PixelStats) + sizeof(SppmIntegrator::VisiblePoint));
  if (const std::int64_t physical = physical_memory_bytes();
      physical > 0 && double(pixels) * per_pixel > double(physical))
    throw OutOfMemory(static_cast<std::size_t>(double(pixels) * per_pixel));

  // Held for the whole render and reused by every iteration: memory stays flat.
  std::vector<PixelStats> pixel_stats(pixels);
  std::vector<SppmIntegrator::VisiblePoint> visible(pixels);
  std::vector<std::vector<Photon>> chunk_photons;
  std::vector<Photon> photons;
  PhotonGrid grid;
  tbb::enumerable_thread_specific<PrimaryBlock> primary_blocks;
  std::atomic<std::uint64_t> total_rays{0}, total_primary_rays{0};
  std::atomic<Clock::rep> total_primary_ticks{0};

  const std::vector<Tile> tiles = make_tiles(settings.width, settings.height, settings.tile_size);
  TileRunner runner(settings.threads);
  // The emission seen directly, where a light shows: camera rays of its own, as for the
  // path tracer (render/camera_emission.h).
  std::optional<CameraEmission> camera_emission;
  if (settings.emitter_samples > 0)
    camera_emission.emplace(scene, accel, camera, filter, settings.width, settings.height, settings.emitter_samples,
                            runner);
  tbb::enumerable_thread_specific<CameraEmission::Scratch> emission_scratch;
  std::atomic<std::uint64_t> emission_rays{0};
  total_rays += camera_emission ? camera_emission->setup_rays() : 0;
  auto current_image = [&](int iterations) {
    ImageRGB image(settings.width, settings.height);
    if (iterations == 0) return image;
    const double n = iterations;
    const double photons_shot = n * static_cast<double>(photons_per_iteration);
    for (std::size_t p = 0; p < pixels; ++p) {
      const PixelStats& s = pixel_stats[p];
      glm::dvec3 L = s.direct / n;
      if (s.radius > 0.0f) L += s.tau / (photons_shot * kPi * double(s.radius) * double(s.radius));
      image.rgb[3 * p] = float(L.x), image.rgb[3 * p + 1] = float(L.y), image.rgb[3 * p + 2] = float(L.z);
    }
    return image;
  };

  int iterations = 0;
  auto last_checkpoint = start;
  for (int iteration = 0; iteration < settings.spp && !must_stop(); ++iteration) {
    // 1. Camera paths: one per pixel, to its visible point.
    runner.run(
        tiles,
        [&](const Tile& tile) {
          std::uint64_t rays = 0, primary_rays = 0;
          Clock::duration primary_time{0};
          PrimaryBlock& primary = primary_blocks.local();
          std::array<glm::vec3, kBlockPixels> seen;
          for (const PixelBlock& block : make_blocks(tile)) {
            primary.generate(camera, filter, block, iteration, settings.seed);
            const bool apart = camera_emission && camera_emission->mark(block, primary, 0);
            primary_time += primary.trace(accel, settings.mode);
            primary_rays += static_cast<std::uint64_t>(primary.size());
            seen.fill(glm::vec3(0.0f));
            if (apart) {
              std::uint64_t added = 0;
              camera_emission->add(block, primary.emission_apart(), iteration, settings.seed, settings.mode,
                                   seen.data(), added, emission_scratch.local());
              rays += added;
              emission_rays.fetch_add(added, std::memory_order_relaxed);
            }
            for (int i = 0; i < block.pixel_count(); ++i) {
              const std::size_t p = static_cast<std::size_t>(block.y0 + i / block.width()) * settings.width +
                                    static_cast<std::size_t>(block.x0 + i % block.width());
              const SppmIntegrator::CameraPath path =
                  sppm.camera_path(primary.ray(i), primary.hit(i), primary.sampler(i), rays,
                                   primary.emission_apart()[i]);
              PixelStats& s = pixel_stats[p];
              s.direct += glm::dvec3(path.L) + glm::dvec3(seen[static_cast<std::size_t>(i)]);
              visible[p] = path.vp;
              if (path.vp.valid && s.radius == 0.0f) s.radius = initial_radius(path.vp.distance);
              if (!(s.radius > 0.0f)) visible[p].valid = false;
            }
          }
          total_rays.fetch_add(rays + primary_rays, std::memory_order_relaxed);
          total_primary_rays.fetch_add(primary_rays, std::memory_order_relaxed);
          total_primary_ticks.fetch_add(primary_time.count(), std::memory_order_relaxed);
        },
        {}, tiles.size());

    // 2. Photons, chunk by chunk, joined in chunk order.
    const auto first_photon = static_cast<std::uint64_t>(iteration) * static_cast<std::uint64_t>(photons_per_iteration);
    total_rays.fetch_add(
        trace_photons_in_chunks(runner, photon_count, chunk_photons,
                                [&](std::size_t i, std::vector<Photon>& out, std::uint64_t& rays) {
                                  sppm.trace_photon(first_photon + i, settings.seed, out, rays);
                                }),
        std::memory_order_relaxed);
    photons.clear();
    for (const std::vector<Photon>& c : chunk_photons) photons.insert(photons.end(), c.begin(), c.end());

    // 3. Gather at the visible points and update their statistics.
    float max_radius = 0.0f;
    for (std::size_t p = 0; p < pixels; ++p)
      if (visible[p].valid) max_radius = std::max(max_radius, pixel_stats[p].radius);
    if (max_radius > 0.0f && !photons.empty()) {
      grid.build(photons, max_radius);
      runner.run_ranges(pixels, 256, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) {
          PixelStats& s = pixel_stats[p];
          const SppmIntegrator::VisiblePoint& vp = visible[p];
          const SppmIntegrator::Gathered g = sppm.gather(vp, grid, s.radius);
          if (g.count == 0) continue;
          const double m = g.count;
          const double n_new = s.n + kAlpha * m;
          const double shrink2 = n_new / (s.n + m);  // (r' / r)^2
          s.tau = (s.tau + glm::dvec3(vp.beta) * glm::dvec3(g.phi)) * shrink2;
          s.n = n_new;
          s.radius = static_cast<float>(double(s.radius) * std::sqrt(shrink2));
        }
      });
    }

    iterations = iteration + 1;
    stats.passes = iterations;
    if (progress) progress(static_cast<std::size_t>(iterations) * tiles.size(), static_cast<std::size_t>(settings.spp) * tiles.size());
    if (control.checkpoint_s > 0.0 && control.on_checkpoint && iterations < settings.spp &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= control.checkpoint_s) {
      control.on_checkpoint(current_image(iterations), iterations);
      last_checkpoint = Clock::now();
    }
  }

  stats.stopped = iterations < settings.spp;
  stats.min_spp = stats.max_spp = static_cast<std::uint32_t>(iterations);
  stats.pixels_past_min_spp = 0;
  stats.rays = total_rays.load();
  stats.path_batches = {};
  stats.path_batches.emission_rays = emission_rays.load();
  stats.setup_rays = camera_emission ? camera_emission->setup_rays() : 0;
  stats.primary_rays = total_primary_rays.load();
  stats.primary_seconds = std::chrono::duration<double>(Clock::duration(total_primary_ticks.load())).count();
  ImageRGB image = current_image(iterations);
  stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return image;
}

}  // namespace lancer
