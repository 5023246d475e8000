// render_image for --integrator sppm: iterations of stochastic progressive photon mapping
// (render/sppm.h) over the whole image, with the renderer's camera rays, threads, stop flag,
// time limit and checkpoints.
#pragma once

#include <cstddef>
#include <cstdint>

#include "render/renderer.h"

namespace lancer {

// The visible points' initial radius without RenderSettings::sppm_radius: this many pixel
// footprints at the point's distance along its camera path (for an orthographic camera, this
// many pixel widths). Progressive photon mapping shrinks it as photons arrive.
inline constexpr float kSppmRadiusPixels = 3.0f;
// Photons per iteration without RenderSettings::photons: one per pixel (as pbrt-v4's SPPM),
// at most this many.
inline constexpr std::int64_t kMaxDefaultPhotons = std::int64_t(1) << 22;
// The most photons an iteration may shoot: the photons they leave are kept for one iteration,
// about 40 bytes per surface met.
inline constexpr std::int64_t kMaxPhotonsPerIteration = std::int64_t(1) << 24;

// settings.spp iterations (fewer when `control` stops the render: it is checked between
// iterations, and the image is that of the iterations finished). One iteration is one pass
// in stats and in the progress and checkpoint callbacks.
ImageRGB render_sppm(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                     const RenderSettings& settings, RenderStats& stats, const ProgressCallback& progress,
                     const RenderControl& control);

}  // namespace lancer
