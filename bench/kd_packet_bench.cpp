// Packet traversal throughput on the 256 x 256 primary rays of bench_scenes.h regrouped
// into 8x8 pixel tiles of 64 rays (bench::tiled_primary_rays):
//   BM_KdPacket/<isa>/primary/<1thread|allthreads>/<scene>        KdTree::intersect_packet per tile
//   BM_KdPacketSingle/<isa>/primary/<1thread|allthreads>/<scene>  the same tiles, one ray at a
//                                                                 time (KdTree::intersect)
//   BM_KdPacketMixedSingle/<isa>/primary/1thread/<scene>          tiles whose rays disagree on a
//       direction sign one ray at a time, the rest as packets (the alternative to handling
//       mixed signs inside the packet kernel)
// 1thread: a plain loop over the tiles; allthreads: tbb::parallel_for over the tiles in the
// default arena (bench::for_each_tile). Counters: rays/s (a rate; the allthreads rows use
// wall-clock time, the 1thread rows CPU time, which a shared machine disturbs less),
// threads, and the number of mixed-sign tiles. Before timing, every packet row checks once
// that its hits equal the single-ray hits bit for bit (bench::check_packets_match_single);
// after timing, every row checks that the timed loop (threads included) left the same hits
// as an untimed pass on one thread.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_scenes.h"
#include "simd/isa.h"

namespace {

using namespace lancer;
using bench::Threads;

bool mixed_signs(const Ray* rays, int count) {
  for (int a = 0; a < 3; ++a) {
    bool neg = false, pos = false;
    for (int i = 0; i < count; ++i) (rays[i].dir[a] < 0.0f ? neg : pos) = true;
    if (neg && pos) return true;
  }
  return false;
}

// One tree per scene and ISA, built on first use: Google Benchmark runs a benchmark's setup
// again for every trial, and a build would cost more than the timed loop.
const KdTree& tree(const std::string& name, Isa isa) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, Isa>, std::unique_ptr<KdTree>> trees;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = trees[{name, isa}];
  if (!slot) slot = std::make_unique<KdTree>(bench::scene(name), KdBuildOptions{}, isa);
  return *slot;
}

enum class Mode { Packet, Single, MixedSingle };

const char* prefix_of(Mode mode) {
  return mode == Mode::Packet   ? "BM_KdPacket/"
         : mode == Mode::Single ? "BM_KdPacketSingle/"
                                : "BM_KdPacketMixedSingle/";
}

std::string name_of(Mode mode, Isa isa, Threads threads, const std::string& scene) {
  return prefix_of(mode) + std::string(isa_name(isa)) + "/primary/" + bench::threads_name(threads) + "/" + scene;
}

void bm_tiles(benchmark::State& state, Isa isa, std::string name, Mode mode, Threads threads) {
  const KdTree& kd = tree(name, isa);
  const std::vector<Ray> rays = bench::tiled_primary_rays(bench::scene(name));
  const std::size_t tiles = rays.size() / bench::kTileRays;
  std::vector<char> mixed(tiles);
  for (std::size_t i = 0; i < tiles; ++i)
    mixed[i] = mixed_signs(rays.data() + i * bench::kTileRays, bench::kTileRays) ? 1 : 0;
  if (mode != Mode::Single) bench::check_packets_match_single(kd, rays, name_of(mode, isa, threads, name));
  std::vector<Hit> hits(rays.size());
  const auto trace_tile = [&](std::size_t tile) {
    const std::size_t first = tile * bench::kTileRays;
    if (mode == Mode::Single || (mode == Mode::MixedSingle && mixed[tile])) {
      for (std::size_t k = first; k < first + bench::kTileRays; ++k) hits[k] = kd.intersect(rays[k]);
    } else {
      kd.intersect_packet(rays.data() + first, hits.data() + first, bench::kTileRays);
    }
  };
  // One untimed pass on this thread gives the hits every timed pass must reproduce.
  bench::for_each_tile(Threads::One, tiles, trace_tile);
  const std::vector<Hit> expected = hits;
  std::int64_t n = 0;
  for (auto _ : state) {
    bench::for_each_tile(threads, tiles, trace_tile);
    benchmark::DoNotOptimize(hits.data());
    benchmark::ClobberMemory();
    n += static_cast<std::int64_t>(rays.size());
  }
  bench::require_same_hits(hits, expected, name_of(mode, isa, threads, name) + ": hits of the timed loop");
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["threads"] = double(bench::thread_count(threads));
  std::size_t mixed_tiles = 0;
  for (char m : mixed) mixed_tiles += static_cast<std::size_t>(m);
  state.counters["mixed_tiles"] = double(mixed_tiles);
}

struct Registration {
  Registration() {
    for (const std::string& name : bench::scene_names())
      for (Isa isa : supported_isas())
        for (const Mode mode : {Mode::Packet, Mode::Single, Mode::MixedSingle})
          for (const Threads threads : {Threads::One, Threads::All}) {
            if (mode == Mode::MixedSingle && threads == Threads::All) continue;
            auto* bm = benchmark::RegisterBenchmark(name_of(mode, isa, threads, name).c_str(), bm_tiles, isa, name,
                                                    mode, threads);
            bm->Unit(benchmark::kMillisecond);
            if (threads == Threads::All) bm->UseRealTime();
          }
  }
} registration;

}  // namespace
