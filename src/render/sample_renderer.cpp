#include "render/sample_renderer.h"

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "render/camera_emission.h"
#include "render/caustic_map.h"
#include "render/coverage.h"
#include "render/debug_integrators.h"
#include "render/light_emission.h"
#include "render/light_tracer.h"
#include "render/lights.h"
#include "render/path.h"
#include "render/pixel_filter.h"
#include "render/whitted.h"

namespace lancer {

struct SampleRenderer::Impl {
  const Scene& scene;
  const Accelerator& accel;
  const PinholeCamera& camera;
  const RenderSettings& settings;
  bool traces_paths = false;
  bool see_through = false;
  std::optional<AreaLights> area_lights;
  std::optional<LightEmission> emission;
  std::optional<CausticMap> caustics;
  std::optional<LightTracer> light_tracer;  // path: the caustics seen directly, where it applies
  TileRunner& tile_runner;  // the light tracer's threads
  std::optional<PathIntegrator> path;
  std::optional<WhittedIntegrator> whitted;
  PixelFilter filter;
  std::optional<CameraEmission> camera_emission;  // path and photon, where emitters show
  // Per thread, reused from wavefront to wavefront: its camera rays and the path tracer's
  // scratch, so the render loop allocates nothing once warm.
  mutable tbb::enumerable_thread_specific<PrimaryBlock> primary_blocks;
  mutable tbb::enumerable_thread_specific<PathIntegrator::Scratch> path_scratch;
  mutable tbb::enumerable_thread_specific<CameraEmission::Scratch> emission_scratch;

  Impl(const Scene& sc, const Accelerator& ac, const PinholeCamera& cam, const RenderSettings& s, TileRunner& runner)
      : scene(sc), accel(ac), camera(cam), settings(s), tile_runner(runner),
        filter(s.filter == PixelFilterType::Gaussian ? PixelFilter::gaussian() : PixelFilter::box()) {
    if (s.integrator == IntegratorKind::Sppm)
      throw std::invalid_argument("render settings: the sppm integrator renders by photon iterations, not samples");
    // Only the chosen integrator is built (the lights only for those that sample them).
    const bool photon = s.integrator == IntegratorKind::Photon;
    traces_paths = s.integrator == IntegratorKind::Path || photon;
    const bool lit = traces_paths || s.integrator == IntegratorKind::Whitted;
    if (lit) area_lights.emplace(scene);
    // --integrator photon: the caustic photon map, shot once before any sample.
    if (photon) {
      emission.emplace(scene, *area_lights, s.environment);
      CausticMap::Settings cs;
      cs.photons = s.photons > 0 ? s.photons : default_caustic_photons(s.width, s.height);
      cs.k = s.caustic_k > 0 ? s.caustic_k : kDefaultCausticK;
      cs.max_radius = s.caustic_radius > 0.0f ? s.caustic_radius : kCausticRadiusOfScene * emission->scene_radius();
      cs.max_depth = s.max_depth;
      cs.seed = s.seed;
      caustics.emplace(scene, accel, *emission, cs, runner);
    }
    if (traces_paths && LightTracer::applies(scene, camera, s, *area_lights))
      light_tracer.emplace(scene, accel, camera, *area_lights, s);
    if (traces_paths)
      path.emplace(scene, accel, *area_lights, s.environment, s.max_depth, s.light_samples,
                   caustics ? &*caustics : nullptr, s.vector_isa.value_or(best_supported_isa()),
                   light_tracer ? &*light_tracer : nullptr);
    if (s.integrator == IntegratorKind::Whitted) whitted.emplace(scene, accel, *area_lights, s.max_depth, s.light_samples);
    if (traces_paths && s.emitter_samples > 0)
      camera_emission.emplace(scene, accel, camera, filter, s.width, s.height, s.emitter_samples, runner);
    see_through = scene_has_coverage(scene);
  }

  // The radiance of every camera ray of a wavefront: the path tracer advances its paths
  // together (PathIntegrator::radiance_block), the others shade one pixel at a time.
  void shade(PrimaryBlock& primary, glm::vec3* L, std::uint64_t& rays) const {
    const int n = primary.size();
    if (traces_paths) {
      path->radiance_block(primary.rays(), primary.hits(), primary.samplers(), n, L, rays, path_scratch.local(),
                           primary.emission_apart());
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
  }
};

SampleRenderer::SampleRenderer(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                               const RenderSettings& settings, TileRunner& runner)
    : impl_(std::make_unique<Impl>(scene, accel, camera, settings, runner)) {}

SampleRenderer::~SampleRenderer() = default;

bool SampleRenderer::render_tile(const Tile& tile, int sample, const BlockWanted& wanted, const BlockTaken& take,
                                 const StopCheck& stop, Counters& counters) const {
  const Impl& im = *impl_;
  PrimaryBlock& primary = im.primary_blocks.local();
  std::array<glm::vec3, kWavefrontPixels> L;
  const std::vector<PixelBlock> blocks = make_blocks(tile);
  std::array<std::size_t, kWavefrontBlocks> chosen;
  std::uint64_t rays = 0;
  for (std::size_t first = 0; first < blocks.size(); first += kWavefrontBlocks) {
    if (stop()) {
      counters.rays += rays;
      return false;
    }
    const std::size_t last = std::min(blocks.size(), first + kWavefrontBlocks);
    std::size_t n = 0;
    for (std::size_t b = first; b < last; ++b)
      if (wanted(blocks[b])) chosen[n++] = b;
    if (n == 0) continue;
    primary.clear();
    std::array<bool, kWavefrontBlocks> apart{};
    for (std::size_t k = 0; k < n; ++k) {
      const PixelBlock& block = blocks[chosen[k]];
      primary.add(im.camera, im.filter, block, sample, im.settings.seed);
      apart[k] = im.camera_emission &&
                 im.camera_emission->mark(block, primary, primary.block_start(static_cast<int>(k)));
    }
    counters.primary_time += primary.trace(im.accel, im.settings.mode);
    counters.primary_rays += static_cast<std::uint64_t>(primary.size());
    rays += static_cast<std::uint64_t>(primary.size());
    im.shade(primary, L.data(), rays);
    for (std::size_t k = 0; k < n; ++k) {
      if (!apart[k]) continue;
      std::uint64_t emission_rays = 0;
      const int start = primary.block_start(static_cast<int>(k));
      im.camera_emission->add(blocks[chosen[k]], primary.emission_apart() + start, sample, im.settings.seed,
                              im.settings.mode, L.data() + start, emission_rays, im.emission_scratch.local());
      rays += emission_rays;
      im.path_scratch.local().stats.emission_rays += emission_rays;
    }
    for (std::size_t k = 0; k < n; ++k) take(blocks[chosen[k]], L.data() + primary.block_start(static_cast<int>(k)));
  }
  counters.rays += rays;
  return true;
}

bool SampleRenderer::traces_light() const { return impl_->light_tracer.has_value(); }

std::uint64_t SampleRenderer::light_paths_per_pass() const {
  return impl_->light_tracer ? impl_->light_tracer->paths_per_pass() : 0;
}

std::uint64_t SampleRenderer::trace_light_pass(int pass, std::vector<glm::dvec3>& sum) const {
  if (!impl_->light_tracer) return 0;
  return impl_->light_tracer->trace_pass(pass, impl_->tile_runner, sum);
}

std::uint64_t SampleRenderer::setup_rays() const {
  return (impl_->caustics ? impl_->caustics->rays() : 0) +
         (impl_->camera_emission ? impl_->camera_emission->setup_rays() : 0);
}

PathBatchStats SampleRenderer::path_batches() const {
  PathBatchStats total{};
  for (const PathIntegrator::Scratch& scratch : impl_->path_scratch) total += scratch.stats;
  return total;
}

}  // namespace lancer
