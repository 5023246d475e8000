#include "render/primary_block.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace lancer {

std::vector<PixelBlock> make_blocks(const Tile& tile) {
  std::vector<PixelBlock> blocks;
  for (int y = tile.y0; y < tile.y1; y += kBlockSide)
    for (int x = tile.x0; x < tile.x1; x += kBlockSide)
      blocks.push_back({x, y, std::min(x + kBlockSide, tile.x1), std::min(y + kBlockSide, tile.y1)});
  return blocks;
}

namespace {
void check_block(const PixelBlock& block) {
  if (block.width() <= 0 || block.height() <= 0 || block.width() > kBlockSide || block.height() > kBlockSide)
    throw std::invalid_argument("primary block: " + std::to_string(block.width()) + "x" +
                                std::to_string(block.height()) + " pixels (expected 1 to " +
                                std::to_string(kBlockSide) + " on a side)");
}
}  // namespace

void PrimaryBlock::clear() {
  sobol_.clear();
  count_ = 0;
  blocks_ = 0;
}

void PrimaryBlock::generate(const PinholeCamera& camera, const PixelFilter& filter, const PixelBlock& block,
                            int sample, std::uint64_t seed) {
  clear();
  add(camera, filter, block, sample, seed);
}

Ray camera_ray(const PinholeCamera& camera, const PixelFilter& filter, int x, int y, SobolSampler& sampler) {
  const glm::vec2 offset = filter.sample_offset(sampler.next2());
  // The lens position, computed only for a thin lens (a pinhole ignores it).
  const glm::vec2 lens = camera.aperture_radius() > 0.0f ? sampler.get2(sampler.dimension()) : glm::vec2(0.0f);
  sampler.skip(2);
  Ray ray = camera.generate(static_cast<float>(x) + 0.5f + offset.x, static_cast<float>(y) + 0.5f + offset.y, lens);
  // The shutter time, one more dimension only when the shutter is open: every other
  // render keeps its samples.
  if (camera.shutter_open()) {
    ray.time = sampler.next1();
    ray = camera.moved(ray);
  }
  return ray;
}

void PrimaryBlock::add(const PinholeCamera& camera, const PixelFilter& filter, const PixelBlock& block, int sample,
                       std::uint64_t seed) {
  check_block(block);
  if (blocks_ == kWavefrontBlocks)
    throw std::invalid_argument("primary block: more than " + std::to_string(kWavefrontBlocks) + " blocks");
  starts_[static_cast<std::size_t>(blocks_)] = count_;
  for (int y = block.y0; y < block.y1; ++y) {
    for (int x = block.x0; x < block.x1; ++x) {
      SobolSampler& sampler = sobol_.emplace_back(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                                  static_cast<std::uint32_t>(sample), seed);
      apart_[static_cast<std::size_t>(count_)] = false;
      rays_[static_cast<std::size_t>(count_++)] = camera_ray(camera, filter, x, y, sampler);
    }
  }
  starts_[static_cast<std::size_t>(++blocks_)] = count_;
}

std::chrono::steady_clock::duration PrimaryBlock::trace(const Accelerator& accel, TraceMode mode) {
  const auto start = std::chrono::steady_clock::now();
  if (mode == TraceMode::Packet) {
    for (int b = 0; b < blocks_; ++b) {
      const int first = block_start(b);
      accel.intersect_packet(rays_.data() + first, hits_.data() + first, block_start(b + 1) - first);
    }
  } else {
    for (std::size_t i = 0; i < static_cast<std::size_t>(count_); ++i) hits_[i] = accel.intersect(rays_[i]);
  }
  return std::chrono::steady_clock::now() - start;
}

}  // namespace lancer
