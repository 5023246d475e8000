// The renderer's unit of primary-ray work: the camera rays of one or more blocks of at most
// 8x8 pixels for one sample index, each block traced together. Neighbouring camera rays
// share an origin and nearly share a direction, so a packet traversal (Wald, Slusallek,
// Benthin & Wagner, "Interactive Rendering with Coherent Ray Tracing", Eurographics 2001)
// visits the same nodes once for the whole block instead of once per ray. The path tracer
// then shades all of them as one wavefront (PathIntegrator::radiance_block): with several
// blocks its batches of secondary rays are bigger, and more of them go as packets.
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
// Blocks of one tile the renderer shades as one wavefront (up to 256 paths). Measured on
// the two Cornell boxes (AVX-512, one thread, same image bytes): 4 blocks rather than 1
// render them 6-9 % faster; 16 were no better than 4 within the noise.
inline constexpr int kWavefrontBlocks = 4;
inline constexpr int kWavefrontPixels = kWavefrontBlocks * kBlockPixels;

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

// The camera ray of sample `sampler` (made for pixel (x, y)) in that pixel, as every
// integrator's camera rays are made: the sampler's first two dimensions place it in the
// pixel by the filter (filter importance sampling: every sample weighs 1; the box filter
// jitters over the pixel's area), the next two on the lens, and when the camera's shutter
// is open one more gives the ray's time. The sampler is left past those dimensions.
Ray camera_ray(const PinholeCamera& camera, const PixelFilter& filter, int x, int y, SobolSampler& sampler);

class PrimaryBlock {
 public:
  PrimaryBlock() { sobol_.reserve(kWavefrontPixels); }

  // The camera rays of sample `sample` of every pixel of `block` (at most kBlockPixels),
  // row-major in the block, for every integrator: one SobolSampler per pixel, seeded by
  // (x, y, sample, seed), makes its camera_ray and then stays with the pixel for shading.
  // Throws
  // std::invalid_argument for an empty or too large block. generate() starts afresh with
  // this block; add() appends it after the blocks already there (at most kWavefrontBlocks).
  void generate(const PinholeCamera& camera, const PixelFilter& filter, const PixelBlock& block, int sample,
                std::uint64_t seed);
  void add(const PinholeCamera& camera, const PixelFilter& filter, const PixelBlock& block, int sample,
           std::uint64_t seed);
  void clear();

  // Closest hits of all the rays: one Accelerator::intersect_packet call per block (Packet)
  // or one Accelerator::intersect per ray (Single). Returns the time spent in those calls only.
  std::chrono::steady_clock::duration trace(const Accelerator& accel, TraceMode mode);

  int block_count() const { return blocks_; }
  // The rays of block b are [block_start(b), block_start(b + 1)), in the order they were added.
  int block_start(int b) const { return starts_[static_cast<std::size_t>(b)]; }

  int size() const { return count_; }
  const Ray& ray(int i) const { return rays_[static_cast<std::size_t>(i)]; }
  const Hit& hit(int i) const { return hits_[static_cast<std::size_t>(i)]; }
  SobolSampler& sampler(int i) { return sobol_[static_cast<std::size_t>(i)]; }
  // All of them, for the integrators that shade a block at once.
  const Ray* rays() const { return rays_.data(); }
  const Hit* hits() const { return hits_.data(); }
  SobolSampler* samplers() { return sobol_.data(); }
  // Per ray: whether the emission it meets at its first surface is estimated apart
  // (render/camera_emission.h: CameraEmission::covers its pixel); false until set.
  const bool* emission_apart() const { return apart_.data(); }
  void set_emission_apart(int i, bool apart) { apart_[static_cast<std::size_t>(i)] = apart; }

 private:
  std::vector<SobolSampler> sobol_;  // rebuilt in place per sample
  std::array<Ray, kWavefrontPixels> rays_{};
  std::array<Hit, kWavefrontPixels> hits_{};
  std::array<bool, kWavefrontPixels> apart_{};
  std::array<int, kWavefrontBlocks + 1> starts_{};
  int blocks_ = 0;
  int count_ = 0;
};

}  // namespace lancer
