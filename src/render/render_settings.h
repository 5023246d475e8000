// What a render is asked to do: image size, samples, integrator and the threads it may use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "render/pixel_filter.h"
#include "simd/isa.h"

namespace lancer {

class Environment;

enum class IntegratorKind { Path, Whitted, Sppm, Photon, Normals, Albedo, Depth, Ao, PrimId };

std::string_view integrator_name(IntegratorKind kind);
std::optional<IntegratorKind> parse_integrator(std::string_view name);

// How primary (camera) rays are traced: Packet hands each 8x8 pixel block to
// Accelerator::intersect_packet at once, Single calls Accelerator::intersect per ray.
// Both give the same hits, so the image never depends on the mode.
enum class TraceMode { Packet, Single };

std::string_view trace_mode_name(TraceMode mode);
std::optional<TraceMode> parse_trace_mode(std::string_view name);

struct RenderSettings {
  int width = 512;
  int height = 512;
  int spp = 16;            // jittered samples per pixel (sppm: iterations, one camera path per pixel each)
  IntegratorKind integrator = IntegratorKind::Path;
  int max_depth = 8;       // path: bounces; whitted: reflection/refraction recursion limit
  // Points sampled on the emissive triangles (each with its shadow ray) per shading point:
  // path, at every bounce, combined with BSDF sampling by MIS; whitted, at each diffuse hit.
  int light_samples = 1;
  int threads = 0;         // 0: all hardware threads
  std::uint64_t seed = 0;
  int tile_size = 16;
  PixelFilterType filter = PixelFilterType::Box;  // pixel reconstruction filter (every integrator)
  // The environment (not owned; null: black background); path and sppm only.
  const Environment* environment = nullptr;
  // sppm: photons shot per iteration (0: one per pixel), and the visible points' initial
  // radius in scene units (0: kSppmRadiusPixels pixel footprints at the point's distance).
  // photon: caustic photons shot in all (0: kCausticPhotonsPerPixel per pixel, at least
  // kMinDefaultCausticPhotons, at most kMaxDefaultPhotons; render/caustic_render.h).
  std::int64_t photons = 0;
  float sppm_radius = 0.0f;
  // photon: the neighbours of the density estimate (0: kDefaultCausticK), and the largest
  // radius they are searched within, in scene units (0: kCausticRadiusOfScene times the
  // scene's bounding-sphere radius; render/caustic_map.h).
  int caustic_k = 0;
  float caustic_radius = 0.0f;
  TraceMode mode = TraceMode::Packet;  // primary rays only; secondary rays are always single
  // path, photon: camera rays per pixel sample that estimate the emission seen directly,
  // where a block of pixels sees an emitter (render/camera_emission.h); 0: the path's own
  // camera ray alone. Not a command-line option: the tests compare against 0.
  int emitter_samples = 4;
  // path: caustics seen directly (camera - non-delta surface - delta bounces - emissive
  // triangle) traced from the lights, where LightTracer::applies (render/light_tracer.h);
  // false: the path tracer finds them alone. Not a command-line option: the tests compare.
  bool light_traced_caustics = true;
  // The instruction set of the path tracer's vector passes (the ray origins, the hits'
  // geometry, the drawn sample values: ray_offset_batch.h, surface_batch.h, sobol_batch.h);
  // none: the best this CPU runs. Every ISA gives the same image; `lancer render --isa`
  // sets it with the kd-tree's.
  std::optional<Isa> vector_isa;
};

// How the path tracer's rays went in batches (one of each kind per bounce of a block), summed.
struct PathBatchStats {
  std::uint64_t continuation_batches = 0, continuation_rays = 0;
  std::uint64_t packet_rays = 0;  // continuation rays traced as packets (coherent batches)
  std::uint64_t shadow_batches = 0, shadow_rays = 0;
  std::uint64_t shadow_packet_rays = 0;  // shadow rays traced as occlusion packets
  // Rays traced one by one after a blocked shadow ray, through the surfaces that cover
  // only part of it (render/coverage.h: cut-outs, BLEND, culled back faces).
  std::uint64_t crossing_rays = 0;
  // Camera rays that estimated the emission seen directly (render/camera_emission.h).
  std::uint64_t emission_rays = 0;
  PathBatchStats& operator+=(const PathBatchStats& o) {
    continuation_batches += o.continuation_batches, continuation_rays += o.continuation_rays;
    packet_rays += o.packet_rays, shadow_batches += o.shadow_batches, shadow_rays += o.shadow_rays;
    shadow_packet_rays += o.shadow_packet_rays, crossing_rays += o.crossing_rays;
    emission_rays += o.emission_rays;
    return *this;
  }
};

// What a finished render reports in the summary line.
struct RenderStats {
  double seconds = 0.0;
  std::uint64_t rays = 0;  // every ray traced: camera, shadow and secondary
  int passes = 0;          // full passes over the image (one sample per pixel each)
  bool stopped = false;    // ended by the stop flag or the time limit before settings.spp
  std::uint32_t min_spp = 0, max_spp = 0;  // samples the pixels got (differ only when stopped mid-pass)
  std::size_t pixels_past_min_spp = 0;     // pixels with more than min_spp samples
  std::uint64_t primary_rays = 0;  // camera rays: width * height * spp
  // Traced before the first sample: the caustic photons, the blocks that show emitters.
  std::uint64_t setup_rays = 0;
  // Traced by the light paths that take the caustics seen directly (render/light_tracer.h).
  std::uint64_t light_rays = 0;
  // Thread-seconds spent inside the primary-ray tracing calls only, summed over threads.
  double primary_seconds = 0.0;
  PathBatchStats path_batches;  // the path tracer's only
};

}  // namespace lancer
