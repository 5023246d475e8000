// Emission seen directly by the camera, estimated with camera rays of its own where the
// image shows an emitter: each pixel sample of such a block adds the mean emission that
// RenderSettings::emitter_samples extra camera rays meet at their first surface, and its
// path leaves that term out (PathIntegrator::radiance_block's emission_apart).
//
// Why: where an emitter's edge crosses a pixel, the pixel's value is its radiance times
// the covered fraction, and a sample either sees the emitter or not; that variance, the
// radiance squared, is the largest of the image (the Cornell box at 256 spp: 12 % of the
// error in 444 of 65,536 pixels). Its k extra rays per sample are together one Owen-
// scrambled Sobol' net of k times the samples, so the term's variance falls like k^1.5
// over an edge, for k camera rays and a material lookup each, only in the blocks that show
// an emitter.
//
// Unbiased: the emission a camera ray meets at an opaque first surface (coverage 1) is
// estimated by these rays alone, and at a first surface of coverage below 1 by the path
// alone: the two split the term. The pixels are chosen from the geometry alone, never from
// a sample, and each by the 8x8 cell of the image it lies in (never by its block or tile,
// which would make the image depend on the tile size): a cell is chosen when a camera ray
// through a corner of one of its pixels, through the lens centre and at mid-shutter, sees
// an emitter, and so are the cells next to it. So the choice cannot correlate with what
// the samples see. A blur wider than 8 pixels (depth of field, motion) or an emitter
// thinner than a pixel can put an emitter's edge outside the chosen cells: those pixels
// keep the path's estimate, still unbiased, only without the gain.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/accelerator.h"
#include "render/camera.h"
#include "render/pixel_filter.h"
#include "render/primary_block.h"
#include "render/render_settings.h"
#include "render/tile_scheduler.h"
#include "scene/scene.h"

namespace lancer {

class CameraEmission {
 public:
  // Finds the cells of a width x height image that show an emitter (none when no material
  // of the scene emits), tracing on `runner`'s threads. `samples` > 0: rays per pixel
  // sample (RenderSettings::emitter_samples). Keeps references to everything given.
  CameraEmission(const Scene& scene, const Accelerator& accel, const PinholeCamera& camera,
                 const PixelFilter& filter, int width, int height, int samples, TileRunner& runner);

  // Whether pixel (x, y) estimates its directly seen emission here: whether its cell does,
  // so that the choice depends on the pixel alone, not on the block or tile it is in.
  bool covers(int x, int y) const;
  // Marks the camera rays of `block`, which `primary` holds from ray `first` on (row-major,
  // as PrimaryBlock::add lays them out), with covers(x, y) (PrimaryBlock::set_emission_apart):
  // the one place the choice is made for every integrator. Returns whether it marked any.
  bool mark(const PixelBlock& block, PrimaryBlock& primary, int first) const;
  // Cells of 8 x 8 pixels that do, of cell_count().
  std::size_t covered_cells() const;
  std::size_t cell_count() const { return cells_.size(); }
  // Rays traced to find them: one per pixel, none without an emissive material.
  std::uint64_t setup_rays() const { return setup_rays_; }

  // Reused from call to call (one per thread).
  struct Scratch {
    std::vector<int> pixels;  // a block's covered pixels
    std::vector<Ray> rays;
    std::vector<Hit> hits;
  };
  // Adds to L[i], for each pixel i of `block` (row-major, as PrimaryBlock lays it out) whose
  // apart[i] mark() set, the mean emission that this estimate's rays of sample `sample` meet at an
  // opaque first surface emitting toward them. The rays are the pixel's camera rays for
  // sample indices samples * sample + j (j < samples) with a seed of their own, traced as
  // packets (one per j, of the block's covered pixels) or one by one as `mode` says (the
  // same hits either way); `rays` counts them.
  void add(const PixelBlock& block, const bool* apart, int sample, std::uint64_t seed, TraceMode mode, glm::vec3* L,
           std::uint64_t& rays, Scratch& scratch) const;

 private:
  // The emission `ray` meets at `hit` as the path would count it at an opaque first surface.
  glm::vec3 emission_at(const Ray& ray, const Hit& hit) const;

  const Scene& scene_;
  const Accelerator& accel_;
  const PinholeCamera& camera_;
  const PixelFilter& filter_;
  int samples_;
  int cells_x_ = 0, cells_y_ = 0;
  std::vector<std::uint8_t> cells_;  // 1: the cell's pixels sample emission here
  std::uint64_t setup_rays_ = 0;
};

}  // namespace lancer
