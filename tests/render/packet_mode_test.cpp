// Primary rays traced as 8x8 packets (--mode packet) or one at a time (--mode single):
// the same image bit for bit on every ISA, the oracle's image, the image of the plain
// pixel-by-pixel loop, blocks that tile each tile exactly, and honest primary-ray counts.
#include "render/primary_block.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "accel/brute_force.h"
#include "accel/kd_tree.h"
#include "render/debug_integrators.h"
#include "render/lights.h"
#include "render/renderer.h"
#include "render/whitted.h"
#include "scene/load_scene.h"
#include "simd/isa.h"
#include "test_paths.h"

namespace lancer {
namespace {

constexpr IntegratorKind kIntegrators[] = {IntegratorKind::Whitted, IntegratorKind::Normals, IntegratorKind::Depth,
                                           IntegratorKind::PrimId};

const Scene& spheres() {
  static const Scene scene = load_scene(test::scenes_dir() / "cornell-box-spheres.gltf");
  return scene;
}

// An image whose sides are not multiples of 8, so tiles and blocks come out partial.
RenderSettings odd_settings(IntegratorKind integrator, TraceMode mode, int tile_size, int threads, int width = 37,
                            int height = 29) {
  RenderSettings s;
  s.width = width;
  s.height = height;
  s.spp = 2;
  s.integrator = integrator;
  s.mode = mode;
  s.tile_size = tile_size;
  s.threads = threads;
  s.seed = 11;
  return s;
}

ImageRGB render(const Accelerator& accel, const RenderSettings& s, RenderStats& stats) {
  const PinholeCamera cam = PinholeCamera::from_desc(spheres().cameras.at(0), s.width, s.height);
  return render_image(spheres(), accel, cam, s, stats);
}

ImageRGB render(const Accelerator& accel, const RenderSettings& s) {
  RenderStats stats;
  return render(accel, s, stats);
}

bool bitwise_equal(const ImageRGB& a, const ImageRGB& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

double sum_of(const ImageRGB& img) {
  double sum = 0.0;
  for (float v : img.rgb) sum += v;
  return sum;
}

std::string describe(const RenderSettings& s) {
  return std::string(integrator_name(s.integrator)) + ", tile " + std::to_string(s.tile_size) + ", " +
         std::to_string(s.threads) + " thread(s)";
}

// Wraps an accelerator and counts how the renderer calls it.
class CountingAccelerator final : public Accelerator {
 public:
  explicit CountingAccelerator(const Accelerator& inner) : inner_(inner) {}

  Hit intersect(const Ray& ray) const override {
    ++intersect_calls;
    return inner_.intersect(ray);
  }
  bool occluded(const Ray& ray) const override { return inner_.occluded(ray); }
  void intersect_packet(const Ray* rays, Hit* hits, int count) const override {
    ++packet_calls;
    packet_rays += static_cast<std::uint64_t>(count);
    int seen = largest_packet.load();
    while (count > seen && !largest_packet.compare_exchange_weak(seen, count)) {
    }
    inner_.intersect_packet(rays, hits, count);
  }
  std::size_t memory_bytes() const override { return inner_.memory_bytes(); }
  std::string_view name() const override { return "counting"; }

  mutable std::atomic<std::uint64_t> intersect_calls{0}, packet_calls{0}, packet_rays{0};
  mutable std::atomic<int> largest_packet{0};

 private:
  const Accelerator& inner_;
};

TEST(TraceMode, NamesRoundTrip) {
  for (TraceMode m : {TraceMode::Packet, TraceMode::Single}) EXPECT_EQ(parse_trace_mode(trace_mode_name(m)), m);
  EXPECT_EQ(trace_mode_name(TraceMode::Packet), "packet");
  EXPECT_EQ(trace_mode_name(TraceMode::Single), "single");
  EXPECT_FALSE(parse_trace_mode("foo").has_value());
  EXPECT_FALSE(parse_trace_mode("").has_value());
  EXPECT_FALSE(parse_trace_mode("Packet").has_value());
  EXPECT_EQ(RenderSettings{}.mode, TraceMode::Packet);
}

// Every pixel of every tile lies in exactly one block of its own tile, at most 8x8.
TEST(PixelBlocks, CoverEachTileExactlyOnceWithoutCrossingIt) {
  for (int tile_size : {1, 5, 8, 12, 16, 20, 64}) {
    const int width = 37, height = 29;
    std::vector<int> covered(static_cast<std::size_t>(width * height), 0);
    for (const Tile& tile : make_tiles(width, height, tile_size)) {
      for (const PixelBlock& b : make_blocks(tile)) {
        ASSERT_GE(b.width(), 1);
        ASSERT_GE(b.height(), 1);
        ASSERT_LE(b.width(), kBlockSide);
        ASSERT_LE(b.height(), kBlockSide);
        ASSERT_TRUE(b.x0 >= tile.x0 && b.x1 <= tile.x1 && b.y0 >= tile.y0 && b.y1 <= tile.y1)
            << "tile size " << tile_size << ": block leaves its tile";
        for (int y = b.y0; y < b.y1; ++y)
          for (int x = b.x0; x < b.x1; ++x) ++covered[static_cast<std::size_t>(y * width + x)];
      }
    }
    for (std::size_t i = 0; i < covered.size(); ++i)
      ASSERT_EQ(covered[i], 1) << "tile size " << tile_size << " pixel " << i;
  }
}

TEST(PixelBlocks, PartialTilesGivePartialBlocks) {
  const std::vector<PixelBlock> twelve = make_blocks({16, 24, 28, 36});  // a 12x12 tile
  ASSERT_EQ(twelve.size(), 4u);
  EXPECT_EQ(twelve[0].pixel_count(), 64);
  EXPECT_EQ(twelve[1].x0, 24);
  EXPECT_EQ(twelve[1].width(), 4);
  EXPECT_EQ(twelve[1].height(), 8);
  EXPECT_EQ(twelve[2].y0, 32);
  EXPECT_EQ(twelve[2].width(), 8);
  EXPECT_EQ(twelve[2].height(), 4);
  EXPECT_EQ(twelve[3].pixel_count(), 16);
  const std::vector<PixelBlock> corner = make_blocks({32, 26, 37, 29});  // 5x3
  ASSERT_EQ(corner.size(), 1u);
  EXPECT_EQ(corner[0].width(), 5);
  EXPECT_EQ(corner[0].height(), 3);
}

// Each ray is the one the pixel's own sampler gives, and the hits are intersect()'s.
TEST(PrimaryBlock, RaysSamplersAndHitsMatchTracingOnePixelAtATime) {
  const KdTree accel(spheres().triangles);
  const PinholeCamera cam = PinholeCamera::from_desc(spheres().cameras.at(0), 37, 29);
  const PixelBlock block{32, 8, 37, 15};  // 5x7
  for (TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
    PrimaryBlock primary;
    primary.generate(cam, PixelFilter::box(), block, 3, 42);
    ASSERT_EQ(primary.size(), 35);
    EXPECT_GT(primary.trace(accel, mode).count(), 0);
    int hits = 0;
    for (int i = 0; i < primary.size(); ++i) {
      const int x = block.x0 + i % block.width(), y = block.y0 + i / block.width();
      SobolSampler alone(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), 3, 42);
      const glm::vec2 offset = PixelFilter::box().sample_offset(alone.next2());
      alone.skip(2);  // the lens, unused by a pinhole
      const Ray expected =
          cam.generate(static_cast<float>(x) + 0.5f + offset.x, static_cast<float>(y) + 0.5f + offset.y);
      ASSERT_EQ(std::memcmp(&primary.ray(i), &expected, sizeof(Ray)), 0) << "pixel " << x << "," << y;
      EXPECT_EQ(primary.sampler(i).dimension(), 4u);
      EXPECT_EQ(primary.sampler(i).next1(), alone.next1()) << "the sampler must continue the pixel's stream";
      const Hit h = accel.intersect(expected);
      EXPECT_EQ(std::memcmp(&primary.hit(i), &h, sizeof(Hit)), 0)
          << trace_mode_name(mode) << " pixel " << x << "," << y;
      hits += h.valid() ? 1 : 0;
    }
    EXPECT_GT(hits, 0);
  }
}

// A wavefront of several blocks holds each block's rays, samplers and hits exactly as the
// block alone gives them, in the order added, and traces each block as its own packet.
TEST(PrimaryBlock, AddedBlocksAreEachTheBlockAloneAndOnePacketEach) {
  const KdTree kd(spheres().triangles);
  const PinholeCamera cam = PinholeCamera::from_desc(spheres().cameras.at(0), 37, 29);
  const std::vector<PixelBlock> blocks = {{0, 0, 8, 8}, {32, 8, 37, 15}, {8, 0, 16, 8}, {30, 28, 31, 29}};
  ASSERT_EQ(static_cast<int>(blocks.size()), kWavefrontBlocks);
  const CountingAccelerator counted(kd);
  PrimaryBlock wave;
  wave.generate(cam, PixelFilter::box(), {16, 16, 24, 24}, 1, 7);  // cleared by clear()
  wave.clear();
  for (const PixelBlock& b : blocks) wave.add(cam, PixelFilter::box(), b, 2, 7);
  wave.trace(counted, TraceMode::Packet);
  EXPECT_EQ(counted.packet_calls.load(), blocks.size());
  ASSERT_EQ(wave.block_count(), kWavefrontBlocks);
  EXPECT_THROW(wave.add(cam, PixelFilter::box(), blocks[0], 2, 7), std::invalid_argument);
  int at = 0;
  for (int b = 0; b < wave.block_count(); ++b) {
    PrimaryBlock alone;
    alone.generate(cam, PixelFilter::box(), blocks[static_cast<std::size_t>(b)], 2, 7);
    alone.trace(kd, TraceMode::Single);
    ASSERT_EQ(wave.block_start(b), at);
    ASSERT_EQ(wave.block_start(b + 1) - at, alone.size());
    for (int i = 0; i < alone.size(); ++i, ++at) {
      EXPECT_EQ(std::memcmp(&wave.ray(at), &alone.ray(i), sizeof(Ray)), 0) << "block " << b << " ray " << i;
      EXPECT_EQ(std::memcmp(&wave.hit(at), &alone.hit(i), sizeof(Hit)), 0) << "block " << b << " ray " << i;
      EXPECT_EQ(wave.sampler(at).next1(), alone.sampler(i).next1()) << "block " << b << " ray " << i;
    }
  }
  EXPECT_EQ(wave.size(), at);
}

TEST(PrimaryBlock, RefusesEmptyOrOversizedBlocks) {
  const PinholeCamera cam = PinholeCamera::from_desc(spheres().cameras.at(0), 37, 29);
  PrimaryBlock primary;
  EXPECT_THROW(primary.generate(cam, PixelFilter::box(), {0, 0, 0, 8}, 0, 0), std::invalid_argument);
  EXPECT_THROW(primary.generate(cam, PixelFilter::box(), {0, 0, 9, 8}, 0, 0), std::invalid_argument);
  EXPECT_THROW(primary.generate(cam, PixelFilter::box(), {0, 0, 8, 9}, 0, 0), std::invalid_argument);
}

class PacketModeIsas : public ::testing::TestWithParam<Isa> {};

// The kd-tree's packet traversal and its single-ray traversal give the same image, bit for
// bit, with every integrator, partial tiles (16, 12 and 40 on a 37x29 image: 40 is one tile
// of 20 blocks, five wavefronts) and several threads.
TEST_P(PacketModeIsas, PacketAndSingleImagesAreBitIdentical) {
  const KdTree accel(spheres().triangles, {}, GetParam());
  for (IntegratorKind integrator : kIntegrators) {
    const ImageRGB reference = render(accel, odd_settings(integrator, TraceMode::Single, 16, 1));
    EXPECT_GT(sum_of(reference), 0.0) << integrator_name(integrator) << ": a black image proves nothing";
    for (int tile_size : {16, 12, 40}) {
      for (TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
        const RenderSettings s = odd_settings(integrator, mode, tile_size, 2);
        EXPECT_TRUE(bitwise_equal(render(accel, s), reference)) << trace_mode_name(mode) << ", " << describe(s);
      }
    }
  }
}

// The kd-tree in packet mode against the brute-force oracle in single mode.
TEST_P(PacketModeIsas, PacketImageEqualsTheOraclesSingleImage) {
  const KdTree accel(spheres().triangles, {}, GetParam());
  const BruteForce oracle(spheres().triangles);
  for (IntegratorKind integrator : kIntegrators) {
    const ImageRGB expected = render(oracle, odd_settings(integrator, TraceMode::Single, 12, 2, 13, 11));
    const ImageRGB packet = render(accel, odd_settings(integrator, TraceMode::Packet, 12, 2, 13, 11));
    EXPECT_GT(sum_of(expected), 0.0) << integrator_name(integrator);
    EXPECT_TRUE(bitwise_equal(packet, expected)) << integrator_name(integrator);
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, PacketModeIsas, ::testing::ValuesIn(supported_isas()),
                         [](const ::testing::TestParamInfo<Isa>& p) { return std::string(isa_name(p.param)); });

// The renderer before blocks: every pixel, every sample, one ray at a time through the
// integrators' own tracing. Blocks and packets must not change a single bit of it, nor the
// number of rays traced.
ImageRGB pixel_by_pixel(const Accelerator& accel, const RenderSettings& s, std::uint64_t& rays) {
  const Scene& scene = spheres();
  const PinholeCamera cam = PinholeCamera::from_desc(scene.cameras.at(0), s.width, s.height);
  const AreaLights area_lights(scene);
  const WhittedIntegrator whitted(scene, accel, area_lights, s.max_depth, s.light_samples);
  ImageRGB image(s.width, s.height);
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      glm::dvec3 sum(0.0);  // the renderer adds up samples in double, in sample order
      for (int i = 0; i < s.spp; ++i) {
        SobolSampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                             static_cast<std::uint32_t>(i), s.seed);
        const glm::vec2 offset = PixelFilter::box().sample_offset(sampler.next2());
        sampler.skip(2);  // the lens, unused by a pinhole
        const Ray ray = cam.generate(static_cast<float>(x) + 0.5f + offset.x, static_cast<float>(y) + 0.5f + offset.y);
        sum += glm::dvec3(s.integrator == IntegratorKind::Whitted
                              ? whitted.radiance(ray, sampler, rays)
                              : debug_radiance(s.integrator, scene, accel, ray, rays));
      }
      image.set(x, y, glm::vec3(sum / static_cast<double>(s.spp)));
    }
  }
  return image;
}

TEST(PacketMode, ImagesAndRayCountsEqualThePixelByPixelRenderer) {
  const KdTree accel(spheres().triangles);
  for (IntegratorKind integrator : kIntegrators) {
    // Three samples: with two, a + b == b + a would hide a change in the order of the sum.
    RenderSettings s = odd_settings(integrator, TraceMode::Single, 12, 2);
    s.spp = 3;
    std::uint64_t expected_rays = 0;
    const ImageRGB expected = pixel_by_pixel(accel, s, expected_rays);
    for (TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
      s.mode = mode;
      RenderStats stats;
      EXPECT_TRUE(bitwise_equal(render(accel, s, stats), expected)) << trace_mode_name(mode) << ", " << describe(s);
      EXPECT_EQ(stats.rays, expected_rays) << trace_mode_name(mode) << ", " << describe(s);
    }
  }
}

TEST(PacketMode, StatsCountEveryPrimaryRayOnceAndItsTime) {
  const KdTree accel(spheres().triangles);
  for (IntegratorKind integrator : kIntegrators) {
    for (TraceMode mode : {TraceMode::Packet, TraceMode::Single}) {
      const RenderSettings s = odd_settings(integrator, mode, 12, 2);
      RenderStats stats;
      render(accel, s, stats);
      const auto primary = static_cast<std::uint64_t>(s.width) * static_cast<std::uint64_t>(s.height) *
                           static_cast<std::uint64_t>(s.spp);
      EXPECT_EQ(stats.primary_rays, primary) << trace_mode_name(mode) << ", " << describe(s);
      EXPECT_GT(stats.primary_seconds, 0.0) << trace_mode_name(mode) << ", " << describe(s);
      if (integrator == IntegratorKind::Whitted)
        EXPECT_GT(stats.rays, stats.primary_rays) << "shadow rays were not counted";
      else
        EXPECT_EQ(stats.rays, stats.primary_rays) << "debug views trace camera rays only";
    }
  }
}

// Packet mode hands whole blocks to intersect_packet and never traces a camera ray alone;
// single mode never calls intersect_packet.
TEST(PacketMode, EachModeUsesItsOwnAcceleratorCall) {
  const KdTree kd(spheres().triangles);
  for (int tile_size : {16, 12}) {
    const RenderSettings packet = odd_settings(IntegratorKind::Depth, TraceMode::Packet, tile_size, 2);
    std::uint64_t blocks = 0;
    for (const Tile& tile : make_tiles(packet.width, packet.height, tile_size)) blocks += make_blocks(tile).size();
    const std::uint64_t primary = static_cast<std::uint64_t>(packet.width * packet.height * packet.spp);

    const CountingAccelerator counted_packet(kd);
    render(counted_packet, packet);
    EXPECT_EQ(counted_packet.packet_calls.load(), blocks * static_cast<std::uint64_t>(packet.spp));
    EXPECT_EQ(counted_packet.packet_rays.load(), primary);
    EXPECT_EQ(counted_packet.largest_packet.load(), kBlockPixels);
    EXPECT_EQ(counted_packet.intersect_calls.load(), 0u);

    const CountingAccelerator counted_single(kd);
    RenderSettings single = packet;
    single.mode = TraceMode::Single;
    render(counted_single, single);
    EXPECT_EQ(counted_single.packet_calls.load(), 0u);
    EXPECT_EQ(counted_single.intersect_calls.load(), primary);
  }
}

TEST(PacketMode, UnknownModeIsRejected) {
  const KdTree accel(spheres().triangles);
  RenderSettings s = odd_settings(IntegratorKind::Depth, TraceMode::Packet, 16, 1);
  s.mode = static_cast<TraceMode>(7);
  RenderStats stats;
  EXPECT_THROW(render(accel, s, stats), std::invalid_argument);
}

}  // namespace
}  // namespace lancer
