// The renderer's unit of primary-ray work: the camera rays of one block of at most 8x8
// pixels for one sample index, traced together. Neighbouring camera rays share an origin
// and nearly share a direction, so a packet traversal (Wald, Slusallek, Benthin & Wagner,
// "Interactive Rendering with Coherent Ray Tracing", Eurographics 2001) visits the same
// nodes once for the whole block instead of once per ray.
//
// Each pixel keeps its own SobolSampler, seeded by (x, y, sample, seed) exactly as for a
// ray traced alone, and the hits are exactly Accelerator::intersect's, so an image does
// not depend on the block shape, the tile size or the trace mode.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "accel/accelerator.h"
#include "render/camera.h"
#include "render/render_settings.h"
#include "render/pixel_filter.h"
#include "render/sobol_sampler.h"
#include "render/tile_scheduler.h"

namespace lancer {

inline constexpr int kBlockSide = 8;
inline constexpr int kBlockPixels = kBlockSide * kBlockSide;

// Pixels [x0, x1) x [y0, y1), at most kBlockSide on a side.
struct PixelBlock {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  int pixel_count() const { return width() * height(); }
};

// Row-major blocks covering `tile` exactly once. Blocks never cross the tile's border: when
// its sides are not multiples of kBlockSide, the last column and row of blocks are smaller.
std::vector<PixelBlock> make_blocks(const Tile& tile);

class PrimaryBlock {
 public:
  PrimaryBlock() { sobol_.reserve(kBlockPixels); }

  // The camera rays of sample `sample` of every pixel of `block` (at most kBlockPixels),
  // row-major in the block, for every integrator: one SobolSampler per pixel, whose first
  // two dimensions place the sample in the pixel by the filter (filter importance sampling:
  // every sample weighs 1; the box filter jitters over the pixel's area) and the next two on
  // the lens; the sampler then stays with the pixel for shading. Throws
  // std::invalid_argument for an empty or too large block.
  void generate(const PinholeCamera& camera, const PixelFilter& filter, const PixelBlock& block, int sample,
                std::uint64_t seed);

  // Closest hits of all the rays: one Accelerator::intersect_packet call (Packet) or one
  // Accelerator::intersect per ray (Single). Returns the time spent in those calls only.
  std::chrono::steady_clock::duration trace(const Accelerator& accel, TraceMode mode);

  int size() const { return count_; }
  const Ray& ray(int i) const { return rays_[static_cast<std::size_t>(i)]; }
  const Hit& hit(int i) const { return hits_[static_cast<std::size_t>(i)]; }
  SobolSampler& sampler(int i) { return sobol_[static_cast<std::size_t>(i)]; }
  // All of them, for the integrators that shade a block at once.
  const Ray* rays() const { return rays_.data(); }
  const Hit* hits() const { return hits_.data(); }
  SobolSampler* samplers() { return sobol_.data(); }

 private:
  std::vector<SobolSampler> sobol_;  // rebuilt in place per sample
  std::array<Ray, kBlockPixels> rays_{};
  std::array<Hit, kBlockPixels> hits_{};
  int count_ = 0;
};

}  // namespace lancer
