#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

#include "render/caustic_map.h"
#include "render/coverage.h"
#include "render/debug_integrators.h"
#include "render/light_emission.h"
#include "render/lights.h"
#include "render/path.h"
#include "render/pixel_filter.h"
#include "render/primary_block.h"
#include "render/render_control.h"
#include "render/render_state.h"
#include "render/sampler.h"
#include "render/sppm_render.h"
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
  if (s.light_samples < 1) fail("light samples must be >= 1");
  if (s.threads < 0) fail("threads must be >= 0");
  if (s.tile_size <= 0) fail("tile size must be positive");
  if (s.mode != TraceMode::Packet && s.mode != TraceMode::Single) fail("unknown trace mode");
  if (scene.material_id.size() != scene.triangle_count() || scene.materials.empty())
    fail("scene " + scene.source + " has no material for some triangles");
  const bool sppm = s.integrator == IntegratorKind::Sppm, photon = s.integrator == IntegratorKind::Photon;
  if (s.environment && s.integrator != IntegratorKind::Path && !sppm && !photon)
    fail("an environment lights only the path, sppm and photon integrators, not " +
         std::string(integrator_name(s.integrator)));
  const std::int64_t most_photons = photon ? kMaxCausticPhotons : kMaxPhotonsPerIteration;
  if (s.photons < 0 || s.photons > most_photons)
    fail(std::string(photon ? "caustic photons" : "photons per iteration") + " must be between 1 and " +
         std::to_string(most_photons) + " (0: default)");
  if (!(s.sppm_radius >= 0.0f) || !std::isfinite(s.sppm_radius)) fail("the sppm radius must be finite and >= 0");
  if (s.caustic_k < 0 || s.caustic_k == 1 || s.caustic_k > kMaxCausticK)
    fail("caustic neighbours must be between 2 and " + std::to_string(kMaxCausticK) + " (0: default)");
  if (!(s.caustic_radius >= 0.0f) || !std::isfinite(s.caustic_radius))
    fail("the caustic radius must be finite and >= 0");
  if (!sppm && !photon && s.photons != 0) fail("photons are for the sppm and photon integrators only");
  if (!sppm && s.sppm_radius != 0.0f) fail("the sppm radius is for the sppm integrator only");
  if (!photon && (s.caustic_k != 0 || s.caustic_radius != 0.0f))
    fail("caustic neighbours and radius are for the photon integrator only");
}

// A state to continue from must be one this render could have left: same size, every pixel
// at `passes` or one more, and no more samples than settings.spp.
void check_state(const RenderState& st, const RenderSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("render state: " + what); };
  if (st.width != s.width || st.height != s.height)
    fail("it is " + std::to_string(st.width) + "x" + std::to_string(st.height) + " but the image is " +
         std::to_string(s.width) + "x" + std::to_string(s.height));
  if (st.sum.size() != st.pixels() || st.count.size() != st.pixels()) fail("sums or counts are not one per pixel");
  if (st.passes < 0) fail(std::to_string(st.passes) + " passes done: a count cannot be negative");
  if (st.passes > s.spp)
    fail(std::to_string(st.passes) + " passes done, more than the " + std::to_string(s.spp) + " asked for");
  const auto ahead = static_cast<std::uint32_t>(st.passes) + (st.passes < s.spp ? 1u : 0u);
  for (std::uint32_t c : st.count)
    if (c < static_cast<std::uint32_t>(st.passes) || c > ahead)
      fail("a pixel has " + std::to_string(c) + " samples after " + std::to_string(st.passes) + " full passes");
}

}  // namespace

ImageRGB render_image(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                      const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress,
                      const RenderControl& control) {
  check_settings(scene, camera, settings);
  if (settings.integrator == IntegratorKind::Sppm) {
    if (control.state != nullptr) throw std::invalid_argument("render settings: the sppm integrator keeps no RenderState");
    return render_sppm(scene, accel, camera, settings, stats, progress, control);
  }
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool timed = control.time_limit_s > 0.0;
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(timed ? control.time_limit_s : 0.0));

  // Per pixel: the sum of its samples in double (a long render adds up millions) and how
  // many there are, so an image stopped mid-pass still averages what each pixel got.
  RenderState own_state;
  RenderState& state = control.state != nullptr ? *control.state : own_state;
  if (state.empty()) state.reset(settings.width, settings.height);
  check_state(state, settings);
  std::vector<glm::dvec3>& sum = state.sum;
  std::vector<std::uint32_t>& count = state.count;
  std::atomic<std::uint64_t> total_rays{0};
  std::atomic<std::uint64_t> total_primary_rays{0};
  std::atomic<Clock::rep> total_primary_ticks{0};  // summed over threads
  std::atomic<bool> halted{false};

  TileRunner runner(settings.threads);
  // Only the chosen integrator is built (the lights only for those that sample them).
  const bool photon = settings.integrator == IntegratorKind::Photon;
  const bool traces_paths = settings.integrator == IntegratorKind::Path || photon;
  const bool lit = traces_paths || settings.integrator == IntegratorKind::Whitted;
  const std::optional<AreaLights> area_lights = lit ? std::optional<AreaLights>(std::in_place, scene) : std::nullopt;
  // --integrator photon: the caustic photon map, shot once before the passes.
  std::optional<LightEmission> emission;
  std::optional<CausticMap> caustics;
  if (photon) {
    emission.emplace(scene, *area_lights, settings.environment);
    CausticMap::Settings cs;
    cs.photons = settings.photons > 0 ? settings.photons : default_caustic_photons(settings.width, settings.height);
    cs.k = settings.caustic_k > 0 ? settings.caustic_k : kDefaultCausticK;
    cs.max_radius = settings.caustic_radius > 0.0f ? settings.caustic_radius
                                                   : kCausticRadiusOfScene * emission->scene_radius();
    cs.max_depth = settings.max_depth;
    cs.seed = settings.seed;
    caustics.emplace(scene, accel, *emission, cs, runner);
    total_rays += caustics->rays();
  }
  std::optional<PathIntegrator> path;
  std::optional<WhittedIntegrator> whitted;
  if (traces_paths)
    path.emplace(scene, accel, *area_lights, settings.environment, settings.max_depth, settings.light_samples,
                 caustics ? &*caustics : nullptr);
  if (settings.integrator == IntegratorKind::Whitted)
    whitted.emplace(scene, accel, *area_lights, settings.max_depth, settings.light_samples);
  const PixelFilter filter =
      settings.filter == PixelFilterType::Gaussian ? PixelFilter::gaussian() : PixelFilter::box();
  // Per thread, reused from wavefront to wavefront: its camera rays and the path tracer's
  // scratch, so the render loop allocates nothing once warm.
  tbb::enumerable_thread_specific<PrimaryBlock> primary_blocks;
  tbb::enumerable_thread_specific<PathIntegrator::Scratch> path_scratch;
  // The radiance of every camera ray of a wavefront: the path tracer advances its paths
  // together (PathIntegrator::radiance_block), the others shade one pixel at a time.
  const bool see_through = scene_has_coverage(scene);
  auto shade_block = [&](PrimaryBlock& primary, glm::vec3* L, std::uint64_t& rays) {
    const int n = primary.size();
    if (traces_paths) {
      path->radiance_block(primary.rays(), primary.hits(), primary.samplers(), n, L, rays, path_scratch.local());
      return;
    }
    for (int i = 0; i < n; ++i) {
      const Ray& ray = primary.ray(i);
      Hit hit = primary.hit(i);
      // The debug views see through cut-outs (coverage 0); Whitted weighs coverage itself.
      if (see_through && settings.integrator != IntegratorKind::Whitted) skip_uncovered(scene, accel, ray, hit, rays);
      switch (settings.integrator) {
        case IntegratorKind::Whitted: L[i] = whitted->radiance_from_hit(ray, hit, primary.sampler(i), rays); break;
        case IntegratorKind::Ao:
          L[i] = ambient_occlusion(scene, accel, ray, hit, see_through, primary.sampler(i), rays);
          break;
        default: L[i] = debug_radiance_from_hit(settings.integrator, scene, ray, hit);
      }
    }
  };
  auto must_stop = [&] {
    if (halted.load(std::memory_order_relaxed)) return true;
    if ((control.stop && control.stop->load(std::memory_order_relaxed) != 0) || (timed && Clock::now() >= deadline)) {
      halted.store(true, std::memory_order_relaxed);
      return true;
    }
    return false;
  };

  // One pass: sample `s` of every pixel, a wavefront of up to kWavefrontBlocks blocks of the
  // tile at a time, each block's camera rays traced together (a packet or one by one), then
  // all of them shaded, each pixel with its own sampler. The stop flag is read before each
  // wavefront.
  const int resumed_pass = state.passes;
  int s = 0;
  auto render_tile = [&](const Tile& tile) {
    std::uint64_t rays = 0;  // per tile, added to the totals once
    std::uint64_t primary_rays = 0;
    Clock::duration primary_time{0};
    PrimaryBlock& primary = primary_blocks.local();
    std::array<glm::vec3, kWavefrontPixels> L;
    const std::vector<PixelBlock> blocks = make_blocks(tile);
    auto pixel = [&](const PixelBlock& block, int i) {
      return static_cast<std::size_t>(block.y0 + i / block.width()) * settings.width +
             static_cast<std::size_t>(block.x0 + i % block.width());
    };
    // A pixel takes sample s only while it has s samples: a resumed render's first pass
    // skips the pixels a stop in the middle of that pass had already given it.
    auto lacks_sample = [&](const PixelBlock& block) {
      for (int i = 0; i < block.pixel_count(); ++i)
        if (count[pixel(block, i)] == static_cast<std::uint32_t>(s)) return true;
      return false;
    };
    std::array<std::size_t, kWavefrontBlocks> chosen;
    for (std::size_t first = 0; first < blocks.size(); first += kWavefrontBlocks) {
      if (must_stop()) break;
      const std::size_t last = std::min(blocks.size(), first + kWavefrontBlocks);
      std::size_t n = 0;
      for (std::size_t b = first; b < last; ++b)
        if (lacks_sample(blocks[b])) chosen[n++] = b;
      if (n == 0) continue;
      primary.clear();
      for (std::size_t k = 0; k < n; ++k) primary.add(camera, filter, blocks[chosen[k]], s, settings.seed);
      primary_time += primary.trace(accel, settings.mode);
      primary_rays += static_cast<std::uint64_t>(primary.size());
      shade_block(primary, L.data(), rays);
      for (std::size_t k = 0; k < n; ++k) {
        const PixelBlock& block = blocks[chosen[k]];
        const glm::vec3* block_L = L.data() + primary.block_start(static_cast<int>(k));
        for (int i = 0; i < block.pixel_count(); ++i) {
          const std::size_t p = pixel(block, i);
          if (count[p] != static_cast<std::uint32_t>(s)) continue;
          sum[p] += glm::dvec3(block_L[i]);
          ++count[p];
        }
      }
    }
    total_rays.fetch_add(rays + primary_rays, std::memory_order_relaxed);
    total_primary_rays.fetch_add(primary_rays, std::memory_order_relaxed);
    total_primary_ticks.fetch_add(primary_time.count(), std::memory_order_relaxed);
  };
  const std::vector<Tile> tiles = make_tiles(settings.width, settings.height, settings.tile_size);
  auto last_checkpoint = start;
  stats.passes = state.passes;
  for (s = state.passes; s < settings.spp && !must_stop(); ++s) {
    runner.run(tiles, render_tile, progress, tiles.size() * static_cast<std::size_t>(settings.spp - resumed_pass));
    if (halted.load()) break;
    stats.passes = state.passes = s + 1;
    if (control.checkpoint_s > 0.0 && control.on_checkpoint && s + 1 < settings.spp &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= control.checkpoint_s) {
      control.on_checkpoint(state.mean(), s + 1);
      last_checkpoint = Clock::now();
    }
  }

  stats.stopped = halted.load();
  const auto [lo, hi] = std::minmax_element(count.begin(), count.end());
  stats.min_spp = *lo;
  stats.max_spp = *hi;
  const std::uint32_t least = *lo;  // (clang 14 cannot capture a structured binding)
  stats.pixels_past_min_spp =
      static_cast<std::size_t>(std::count_if(count.begin(), count.end(), [least](std::uint32_t c) { return c > least; }));
  stats.rays = total_rays.load();
  stats.path_batches = {};
  for (const PathIntegrator::Scratch& scratch : path_scratch) stats.path_batches += scratch.stats;
  stats.primary_rays = total_primary_rays.load();
  stats.primary_seconds = std::chrono::duration<double>(Clock::duration(total_primary_ticks.load())).count();
  ImageRGB image = state.mean();
  stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return image;
}

}  // namespace lancer
