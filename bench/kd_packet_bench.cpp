// Packet traversal throughput: BM_KdPacket/<isa>/primary/<scene> traces the 256 x 256
// primary rays of bench_scenes.h as 8x8 pixel tiles of 64 rays (KdTree::intersect_packet);
// BM_KdPacketSingle/<isa>/primary/<scene> traces the same tiles, in the same order, one ray
// at a time (KdTree::intersect), for comparison; BM_KdPacketMixedSingle/... sends the tiles
// whose rays disagree on a direction sign one ray at a time and the rest as packets (the
// alternative to handling mixed signs inside the packet kernel). One thread, rays/s as a
// rate counter, and the number of mixed-sign tiles.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_scenes.h"
#include "simd/isa.h"

namespace {

using namespace lancer;

// primary_rays come in row order of a 256 x 256 image; regroup them tile by tile.
std::vector<Ray> tiled_primary_rays(const TriangleSoA& t) {
  const std::vector<Ray> rows = bench::primary_rays(t);
  constexpr int kSize = 256, kTile = 8;
  std::vector<Ray> tiled;
  tiled.reserve(rows.size());
  for (int ty = 0; ty < kSize; ty += kTile)
    for (int tx = 0; tx < kSize; tx += kTile)
      for (int y = ty; y < ty + kTile; ++y)
        for (int x = tx; x < tx + kTile; ++x) tiled.push_back(rows[std::size_t(y) * kSize + std::size_t(x)]);
  return tiled;
}

bool mixed_signs(const Ray* rays, int count) {
  for (int a = 0; a < 3; ++a) {
    bool neg = false, pos = false;
    for (int i = 0; i < count; ++i) (rays[i].dir[a] < 0.0f ? neg : pos) = true;
    if (neg && pos) return true;
  }
  return false;
}

enum class Mode { Packet, Single, MixedSingle };

void bm_tiles(benchmark::State& state, Isa isa, std::string name, Mode mode) {
  const TriangleSoA& t = bench::scene(name);
  const KdTree kd(t, {}, isa);
  const std::vector<Ray> rays = tiled_primary_rays(t);
  std::vector<char> mixed;
  for (std::size_t i = 0; i < rays.size(); i += 64) mixed.push_back(mixed_signs(rays.data() + i, 64) ? 1 : 0);
  std::vector<Hit> hits(rays.size());
  std::int64_t n = 0;
  for (auto _ : state) {
    if (mode != Mode::Single) {
      for (std::size_t i = 0; i < rays.size(); i += 64) {
        if (mode == Mode::MixedSingle && mixed[i / 64]) {
          for (std::size_t k = i; k < i + 64; ++k) hits[k] = kd.intersect(rays[k]);
        } else {
          kd.intersect_packet(rays.data() + i, hits.data() + i, 64);
        }
      }
    } else {
      for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = kd.intersect(rays[i]);
    }
    benchmark::DoNotOptimize(hits.data());
    n += static_cast<std::int64_t>(rays.size());
  }
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  std::size_t mixed_tiles = 0;
  for (char m : mixed) mixed_tiles += static_cast<std::size_t>(m);
  state.counters["mixed_tiles"] = double(mixed_tiles);
}

struct Registration {
  Registration() {
    for (const std::string& name : bench::scene_names())
      for (Isa isa : supported_isas())
        for (const Mode mode : {Mode::Packet, Mode::Single, Mode::MixedSingle}) {
          const char* prefix = mode == Mode::Packet   ? "BM_KdPacket/"
                               : mode == Mode::Single ? "BM_KdPacketSingle/"
                                                      : "BM_KdPacketMixedSingle/";
          const std::string bm = prefix + std::string(isa_name(isa)) + "/primary/" + name;
          benchmark::RegisterBenchmark(bm.c_str(), bm_tiles, isa, name, mode)->Unit(benchmark::kMillisecond);
        }
  }
} registration;

}  // namespace
