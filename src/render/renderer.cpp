#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "render/caustic_map.h"
#include "render/render_control.h"
#include "render/render_state.h"
#include "render/sample_renderer.h"
#include "render/sppm_render.h"
#include "render/tile_scheduler.h"

namespace lancer {

void check_render_settings(const Scene& scene, const PinholeCamera& camera, const RenderSettings& s) {
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
  // The emission estimate's rays take sample indices spp * emitter_samples (32 bits).
  if (s.emitter_samples < 0 || s.emitter_samples > 64) fail("emitter samples must be between 0 and 64");
  if (static_cast<std::uint64_t>(s.spp) * static_cast<std::uint64_t>(s.emitter_samples) > (std::uint64_t{1} << 32))
    fail("samples per pixel times emitter samples must be at most 2^32");
  if (s.mode != TraceMode::Packet && s.mode != TraceMode::Single) fail("unknown trace mode");
  if (scene.material_id.size() != scene.triangle_count() || scene.materials.empty())
    fail("scene " + scene.source + " has no material for some triangles");
  const bool sppm = s.integrator == IntegratorKind::Sppm, photon = s.integrator == IntegratorKind::Photon;
  if (s.environment && s.integrator != IntegratorKind::Path && !sppm && !photon)
    fail("an environment lights only the path, sppm and photon integrators, not " +
         std::string(integrator_name(s.integrator)));
  // Photons leave the lights with no time of their own, and a photon map gathers them at
  // every time of the shutter: moving geometry would be met in the wrong place.
  if ((sppm || photon) && (camera.shutter_open() || !scene.instancing.motions.empty()))
    fail("motion blur (--shutter) works with the path, whitted and debug integrators, not " +
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

void check_render_state(const RenderState& st, const RenderSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("render state: " + what); };
  if (st.width != s.width || st.height != s.height)
    fail("it is " + std::to_string(st.width) + "x" + std::to_string(st.height) + " but the image is " +
         std::to_string(s.width) + "x" + std::to_string(s.height));
  if (st.sum.size() != st.pixels() || st.count.size() != st.pixels()) fail("sums or counts are not one per pixel");
  if (st.passes < 0) fail(std::to_string(st.passes) + " passes done: a count cannot be negative");
  if (st.passes > s.spp)
    fail(std::to_string(st.passes) + " passes done, more than the " + std::to_string(s.spp) + " asked for");
  for (std::uint32_t c : st.count)
    if (c < static_cast<std::uint32_t>(st.passes) || c > static_cast<std::uint32_t>(s.spp))
      fail("a pixel has " + std::to_string(c) + " samples after " + std::to_string(st.passes) +
           " full passes of " + std::to_string(s.spp));
  // (Light passes may run ahead of the samples: a distributed render's rank 0 traces them
  // while the others sample.)
  if (st.light_passes < 0) fail(std::to_string(st.light_passes) + " light passes done: a count cannot be negative");
  if (st.light_passes > 0 && st.light.size() != st.pixels()) fail("light sums are not one per pixel");
  if (!st.pending.empty() && st.pending.size() != st.pixels()) fail("a pending light pass that is not one sum per pixel");
}

void check_light_state(RenderState& state, std::uint64_t paths) {
  if (paths == 0) {
    if (state.light_passes > 0 || !state.pending.empty())
      throw std::invalid_argument("render state: it holds light-traced caustics, which this render leaves to its paths");
    return;
  }
  if ((state.light_passes > 0 || !state.pending.empty()) && state.light_paths != paths)
    throw std::invalid_argument("render state: its light passes have " + std::to_string(state.light_paths) +
                                " paths each, this render traces " + std::to_string(paths));
  // Samples without any light pass: rendered without light tracing, they counted the paths
  // it shares at full weight. (A render with it traces light pass 0 before any sample; later
  // light passes a distributed render had not traced yet are traced on resuming.)
  if (state.passes > 0 && state.light_passes == 0 && state.pending.empty())
    throw std::invalid_argument("render state: " + std::to_string(state.passes) +
                                " passes of samples but no light paths: it was not rendered with the light-traced "
                                "caustics this render adds");
  state.light_paths = paths;
}

std::uint64_t trace_pending_light(const SampleRenderer& sampler, RenderState& state) {
  if (!state.pending.empty()) return 0;
  state.pending.assign(state.pixels(), glm::dvec3(0.0));
  return sampler.trace_light_pass(state.light_passes, state.pending);
}

std::uint64_t complete_light_passes(const SampleRenderer& sampler, RenderState& state, int passes,
                                    const std::function<bool()>& stop) {
  std::uint64_t rays = 0;
  while (sampler.traces_light() && state.light_passes < passes && !stop()) {
    rays += trace_pending_light(sampler, state);
    state.commit_pending();
  }
  return rays;
}

ImageRGB render_image(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                      const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress,
                      const RenderControl& control) {
  check_render_settings(scene, camera, settings);
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
  check_render_state(state, settings);
  std::vector<glm::dvec3>& sum = state.sum;
  std::vector<std::uint32_t>& count = state.count;
  std::atomic<std::uint64_t> total_rays{0};
  std::atomic<std::uint64_t> total_primary_rays{0};
  std::atomic<Clock::rep> total_primary_ticks{0};  // summed over threads
  std::atomic<bool> halted{false};
  std::uint64_t light_rays = 0;  // traced on this thread, between passes

  TileRunner runner(settings.threads);
  const SampleRenderer sampler(scene, accel, camera, settings, runner);
  total_rays += sampler.setup_rays();
  check_light_state(state, sampler.light_paths_per_pass());
  auto must_stop = [&] {
    if (halted.load(std::memory_order_relaxed)) return true;
    if ((control.stop && control.stop->load(std::memory_order_relaxed) != 0) || (timed && Clock::now() >= deadline)) {
      halted.store(true, std::memory_order_relaxed);
      return true;
    }
    return false;
  };

  // One pass: sample `s` of every pixel that has s samples, so a resumed render's pixels
  // each take their next sample in order, whatever the stop left them with (a stop in the
  // middle of a pass, or a distributed render's tiles at different passes).
  const int resumed_pass = state.passes;
  int s = 0;
  auto render_tile = [&](const Tile& tile) {
    SampleRenderer::Counters counters;  // per tile, added to the totals once
    auto pixel = [&](const PixelBlock& block, int i) {
      return static_cast<std::size_t>(block.y0 + i / block.width()) * settings.width +
             static_cast<std::size_t>(block.x0 + i % block.width());
    };
    auto lacks_sample = [&](const PixelBlock& block) {
      for (int i = 0; i < block.pixel_count(); ++i)
        if (count[pixel(block, i)] == static_cast<std::uint32_t>(s)) return true;
      return false;
    };
    auto add_samples = [&](const PixelBlock& block, const glm::vec3* L) {
      for (int i = 0; i < block.pixel_count(); ++i) {
        const std::size_t p = pixel(block, i);
        if (count[p] != static_cast<std::uint32_t>(s)) continue;
        sum[p] += glm::dvec3(L[i]);
        ++count[p];
      }
    };
    sampler.render_tile(tile, s, lacks_sample, add_samples, must_stop, counters);
    total_rays.fetch_add(counters.rays, std::memory_order_relaxed);
    total_primary_rays.fetch_add(counters.primary_rays, std::memory_order_relaxed);
    total_primary_ticks.fetch_add(counters.primary_time.count(), std::memory_order_relaxed);
  };
  const std::vector<Tile> tiles = make_tiles(settings.width, settings.height, settings.tile_size);
  auto last_checkpoint = start;
  stats.passes = state.passes;
  for (s = state.passes; s < settings.spp && !must_stop(); ++s) {
    // The light tracer's pass s before the samples of pass s, pending until the pass is done
    // (and first those a resumed distributed render's state had not traced yet).
    light_rays += complete_light_passes(sampler, state, s, must_stop);
    if (sampler.traces_light() && state.light_passes == s && !must_stop())
      light_rays += trace_pending_light(sampler, state);
    if (halted.load()) break;
    runner.run(tiles, render_tile, progress, tiles.size() * static_cast<std::size_t>(settings.spp - resumed_pass));
    if (halted.load()) break;
    if (state.light_passes == s) state.commit_pending();
    stats.passes = state.passes = s + 1;
    if (control.checkpoint_s > 0.0 && control.on_checkpoint && s + 1 < settings.spp &&
        std::chrono::duration<double>(Clock::now() - last_checkpoint).count() >= control.checkpoint_s) {
      control.on_checkpoint(state.mean(), s + 1);
      last_checkpoint = Clock::now();
    }
  }

  // A resumed state whose samples were all there but not its light passes (a distributed
  // render stopped as it ended) gets the rest.
  if (!halted.load() && state.passes >= settings.spp)
    light_rays += complete_light_passes(sampler, state, settings.spp, must_stop);
  stats.stopped = halted.load();
  const auto [lo, hi] = std::minmax_element(count.begin(), count.end());
  stats.min_spp = *lo;
  stats.max_spp = *hi;
  const std::uint32_t least = *lo;  // (clang 14 cannot capture a structured binding)
  stats.pixels_past_min_spp =
      static_cast<std::size_t>(std::count_if(count.begin(), count.end(), [least](std::uint32_t c) { return c > least; }));
  stats.rays = total_rays.load() + light_rays;
  stats.light_rays = light_rays;
  stats.path_batches = sampler.path_batches();
  stats.primary_rays = total_primary_rays.load();
  stats.setup_rays = sampler.setup_rays();
  stats.primary_seconds = std::chrono::duration<double>(Clock::duration(total_primary_ticks.load())).count();
  ImageRGB image = state.mean();
  stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return image;
}

}  // namespace lancer
