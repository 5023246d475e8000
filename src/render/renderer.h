// The public entry point of the renderer: one call renders one image.
#pragma once

#include <cstddef>
#include <functional>

#include "accel/accelerator.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/render_control.h"
#include "render/render_settings.h"
#include "render/render_state.h"
#include "render/sample_renderer.h"
#include "scene/scene.h"

namespace lancer {

// Called from worker threads after each tile of each pass (total = tiles * spp); must be
// thread-safe on the caller's side.
using ProgressCallback = std::function<void(std::size_t tiles_done, std::size_t tiles_total)>;

// Renders settings.width x settings.height pixels (the camera must have the same size)
// with settings.spp jittered samples per pixel, box-filtered, progressively: pass s adds
// sample s of every pixel, so the image after k passes is the same as a render with
// spp = k. The image depends only on the inputs and settings.seed, never on
// settings.threads or settings.tile_size. `control` may end the render early (stop flag,
// time limit: the image then averages what each pixel got) and asks for checkpoints; with
// control.state it continues a render from the exact sums and counts another left, pixel by
// pixel (a stop mid-pass included), and ends with the uninterrupted render's image.
// `accel` must have been built over scene.triangles. Throws std::invalid_argument on
// invalid settings. Fills stats: seconds, rays (every ray traced), primary_rays,
// primary_seconds and, for the path tracer, its batch counts. Camera rays are traced in
// blocks of at most 8x8 pixels inside each tile, as packets or one by one as settings.mode
// says; the image is the same either way. The path tracer then advances the paths of up to
// kWavefrontBlocks blocks of a tile together (PathIntegrator::radiance_block); the other
// integrators shade pixel by pixel. IntegratorKind::Sppm runs render_sppm
// (render/sppm_render.h): settings.spp iterations of progressive photon mapping.
// IntegratorKind::Photon first builds a caustic photon map (render/caustic_map.h) and then
// runs the path tracer with it. Where LightTracer::applies, each pass of the path tracer
// also traces its light paths (render/light_tracer.h) before its samples; their sums are
// RenderState's light sums, and stats.light_rays counts their rays.
// Throws std::invalid_argument ("render settings: ...") unless `settings` can render `scene`
// through `camera`: render_image's first step, for other drivers of SampleRenderer too.
void check_render_settings(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings);

// Throws std::invalid_argument ("render state: ...") unless a render with `settings` can
// continue from `state`: the image's size, every pixel with at least state.passes and at
// most settings.spp samples. (One process stopped mid-pass leaves pixels at `passes` or one
// more; a distributed render stopped early leaves its tiles further apart.)
void check_render_state(const RenderState& state, const RenderSettings& settings);

// Readies `state` for light passes of `paths` light paths each (SampleRenderer::
// light_paths_per_pass; 0: the render traces none). Throws std::invalid_argument ("render
// state: ...") when the state holds light passes this render cannot continue.
void check_light_state(RenderState& state, std::uint64_t paths);

// Traces the light pass state.light_passes into state.pending (zeroed first) unless it holds
// that pass already; returns its rays.
std::uint64_t trace_pending_light(const SampleRenderer& sampler, RenderState& state);

// Traces and commits light passes until state.light_passes reaches `passes` (none without
// light tracing) or stop() says so; returns their rays.
std::uint64_t complete_light_passes(const SampleRenderer& sampler, RenderState& state, int passes,
                                    const std::function<bool()>& stop);

ImageRGB render_image(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                      const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress = {},
                      const RenderControl& control = {});

}  // namespace lancer
