// Where an image's samples come from, for every integrator but sppm: camera rays of one
// sample index for the blocks of a tile, traced as packets or one by one, then shaded. The
// progressive renderer (renderer.h) adds them into its per-pixel sums; a distributed
// render's workers (dist/) compute them for rank 0, which adds them in the same order.
// A sample depends only on its pixel, its index and the seed, never on which tile, thread,
// process or machine computed it.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/camera.h"
#include "render/primary_block.h"
#include "render/render_settings.h"
#include "render/tile_scheduler.h"
#include "scene/scene.h"

namespace lancer {

class SampleRenderer {
 public:
  // Work done by one caller, to be added into RenderStats.
  struct Counters {
    std::uint64_t rays = 0;  // every ray, camera rays included
    std::uint64_t primary_rays = 0;
    std::chrono::steady_clock::duration primary_time{0};  // inside the camera-ray tracing calls
  };
  // Which blocks of a tile to sample (the others are skipped).
  using BlockWanted = std::function<bool(const PixelBlock&)>;
  // Receives a sampled block's radiance, one value per pixel, row-major in the block.
  using BlockTaken = std::function<void(const PixelBlock&, const glm::vec3*)>;
  // Read before each wavefront; true: stop.
  using StopCheck = std::function<bool()>;

  // Builds only the integrator settings.integrator names (not sppm: std::invalid_argument).
  // --integrator photon shoots its caustic photon map here, on `runner`'s threads. Keeps
  // references to everything given; all must outlive it, and settings must have been checked
  // (render_image does).
  SampleRenderer(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                 const RenderSettings& settings, TileRunner& runner);
  ~SampleRenderer();
  SampleRenderer(const SampleRenderer&) = delete;
  SampleRenderer& operator=(const SampleRenderer&) = delete;

  // Sample `sample` of the pixels of `tile`, a wavefront of up to kWavefrontBlocks blocks at a
  // time, skipping blocks `wanted` refuses. Thread-safe: each thread keeps its own scratch.
  // Returns false when `stop` said so before the tile was done (blocks already taken stay).
  bool render_tile(const Tile& tile, int sample, const BlockWanted& wanted, const BlockTaken& take,
                   const StopCheck& stop, Counters& counters) const;

  // Whether light paths take the caustics seen directly (render/light_tracer.h): then every
  // pass also needs trace_light_pass, whose sums RenderState keeps apart from the pixels'.
  bool traces_light() const;
  std::uint64_t light_paths_per_pass() const;  // 0 without light tracing
  // Adds light pass `pass`'s splats into sum (one per pixel, row-major), on the runner given
  // at construction; returns its rays. Not from two threads at once.
  std::uint64_t trace_light_pass(int pass, std::vector<glm::dvec3>& sum) const;

  // Rays traced while setting up (the caustic photons, the blocks that show emitters), not
  // in any Counters.
  std::uint64_t setup_rays() const;
  // The path tracer's batch counts, summed over every thread so far.
  PathBatchStats path_batches() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lancer
