// Scenes and rays shared by the benchmark programs (lancer_bench_micro and
// lancer_bench_embree), so that Lancer and the Embree baseline run on the same triangles
// and the same rays.
//
// Scenes: "spheres" (procedural, about 100k triangles of spheres of different sizes and
// tessellations) and "bunny" (stanford-bunny.obj from LANCER_MODELS_DIR, only when present).
// Rays: a 256 x 256 pinhole camera ("primary"), the same rays regrouped into 8x8 pixel
// tiles for packet traversal ("tiled"), and one diffuse bounce from every primary hit
// ("diffuse"); all deterministic. Tiles are traced on one thread or on all of them
// (for_each_tile), the same way by every program.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "accel/accelerator.h"
#include "accel/kd_tree.h"
#include "accel/ray_offset.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "simd/splitmix64.h"

namespace lancer::bench {

// The shared meshes: the compile definition LANCER_MODELS_DIR (set in bench/CMakeLists.txt),
// unless the environment variable of the same name overrides it.
inline std::filesystem::path models_dir() {
  if (const char* env = std::getenv("LANCER_MODELS_DIR")) return env;
  return LANCER_MODELS_DIR;
}

// The scenes available on this machine: "spheres", and "bunny" when the mesh is present.
inline std::vector<std::string> scene_names() {
  std::vector<std::string> names{"spheres"};
  if (std::filesystem::exists(models_dir() / "stanford-bunny.obj")) names.push_back("bunny");
  return names;
}

// Scenes are built or loaded once, on first use, and kept for the program's lifetime.
inline const TriangleSoA& scene(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Scene>();
    if (name == "bunny") {
      *slot = load_scene(models_dir() / "stanford-bunny.obj");
    } else {  // "spheres"
      append_icosphere(*slot, {0.0f, 0.0f, 0.0f}, 1.0f, 6, 0);
      append_icosphere(*slot, {2.5f, 0.0f, 0.5f}, 0.6f, 4, 0);
      append_uv_sphere(*slot, {-2.0f, 0.5f, -0.5f}, 0.8f, 96, 48, 0);
      for (int i = 0; i < 8; ++i) append_icosphere(*slot, {-3.0f + 0.8f * float(i), -1.8f, 0.0f}, 0.3f, 2, 0);
    }
  }
  return slot->triangles;
}

// A float in [0, 1) from a splitmix64 stream whose state is `s`.
inline float unit(std::uint64_t& s) { return float(splitmix64_mix(s += 0x9E3779B97F4A7C15ull) >> 40) * 0x1.0p-24f; }

// The primary camera's image is kImageSize x kImageSize pixels; a tile is kTileSize x
// kTileSize pixels, kTileRays consecutive rays of tiled_primary_rays.
inline constexpr int kImageSize = 256;
inline constexpr int kTileSize = 8;
inline constexpr int kTileRays = kTileSize * kTileSize;
static_assert(kImageSize % kTileSize == 0);

// An n x n (256 x 256 by default) pinhole camera looking at the scene's centre from 1.2 box
// diagonals away, in row order.
inline std::vector<Ray> primary_rays(const TriangleSoA& t, int n = kImageSize) {
  const Bounds3 b = t.bounds();
  const glm::vec3 c = b.center(), e = b.extent();
  const float diag = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  const glm::vec3 eye = c + glm::vec3(0.3f, 0.4f, 1.0f) * (1.2f * diag);
  const glm::vec3 fwd = glm::normalize(c - eye);
  const glm::vec3 right = glm::normalize(glm::vec3(fwd.z, 0.0f, -fwd.x));
  const glm::vec3 up = glm::vec3(right.y * fwd.z - right.z * fwd.y, right.z * fwd.x - right.x * fwd.z,
                                 right.x * fwd.y - right.y * fwd.x);
  std::vector<Ray> rays;
  rays.reserve(n * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Ray r;
      r.org = eye;
      const float sx = (x + 0.5f) / n - 0.5f, sy = (y + 0.5f) / n - 0.5f;
      r.dir = fwd + 0.8f * (sx * right + sy * up);
      rays.push_back(r);
    }
  return rays;
}

// The rays of primary_rays regrouped tile by tile: 8x8 pixel tiles in row order of tiles,
// each tile's 64 rays consecutive and in row order inside the tile (so rays [16k, 16k + 16)
// of a tile are two of its rows and [8k, 8k + 8) one row).
// n must be a multiple of kTileSize.
inline std::vector<Ray> tiled_primary_rays(const TriangleSoA& t, int n = kImageSize) {
  const std::vector<Ray> rows = primary_rays(t, n);
  std::vector<Ray> tiled;
  tiled.reserve(rows.size());
  for (int ty = 0; ty < n; ty += kTileSize)
    for (int tx = 0; tx < n; tx += kTileSize)
      for (int y = ty; y < ty + kTileSize; ++y)
        for (int x = tx; x < tx + kTileSize; ++x) tiled.push_back(rows[std::size_t(y) * std::size_t(n) + std::size_t(x)]);
  return tiled;
}

// How the benchmarks spread tiles over threads. One: a plain loop on the calling thread
// (neither Lancer's nor Embree's traversal starts threads of its own). All: tbb::parallel_for
// in the default task arena, every hardware thread.
enum class Threads { One, All };

// The ray set's name in benchmark rows: "primary" for the default image size, else
// "primary<n>" (e.g. primary1024: 16 times the rays, so each 8x8 tile is 4x4 times more
// coherent).
inline std::string primary_set_name(int n) { return n == kImageSize ? "primary" : "primary" + std::to_string(n); }

inline const char* threads_name(Threads threads) { return threads == Threads::One ? "1thread" : "allthreads"; }

// The number of threads a Threads mode traces with (the "threads" counter of the rows):
// the default arena's size, unless a tbb::global_control limits it.
inline int thread_count(Threads threads) {
  if (threads == Threads::One) return 1;
  const std::size_t allowed = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(std::min<std::size_t>(std::size_t(tbb::this_task_arena::max_concurrency()), allowed));
}

// Tiles per parallel_for chunk, at least: a few, so that scheduling costs little next to
// tracing while 1024 tiles still balance over the threads.
inline constexpr std::size_t kTileGrain = 4;

// Calls trace_tile(tile) for every tile in [0, tiles).
template <class TraceTile>
void for_each_tile(Threads threads, std::size_t tiles, const TraceTile& trace_tile) {
  if (threads == Threads::One) {
    for (std::size_t i = 0; i < tiles; ++i) trace_tile(i);
    return;
  }
  using Range = tbb::blocked_range<std::size_t>;
  tbb::parallel_for(Range(0, tiles, kTileGrain), [&](const Range& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) trace_tile(i);
  });
}

// Same triangle and bit-identical t, u and v.
inline bool same_hit(const Hit& a, const Hit& b) {
  return a.prim == b.prim && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
         std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
         std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

// Aborts the program loudly, naming `what`, unless got[i] and expected[i] are the same hit
// for every i: a benchmark whose hits are wrong measures the wrong work.
inline void require_same_hits(const std::vector<Hit>& got, const std::vector<Hit>& expected, const std::string& what) {
  if (got.size() != expected.size()) {
    std::fprintf(stderr, "%s: %zu hits, expected %zu\n", what.c_str(), got.size(), expected.size());
    std::abort();
  }
  for (std::size_t i = 0; i < got.size(); ++i) {
    const Hit &g = got[i], &e = expected[i];
    if (same_hit(g, e)) continue;
    std::fprintf(stderr, "%s: ray %zu (tile %zu): prim %u t %a u %a v %a, expected prim %u t %a u %a v %a\n",
                 what.c_str(), i, i / kTileRays, g.prim, double(g.t), double(g.u), double(g.v), e.prim, double(e.t),
                 double(e.u), double(e.v));
    std::abort();
  }
}

// The packet benchmarks promise the single-ray hits: intersect_packet over 64-ray tiles must
// give exactly what intersect gives ray by ray. Checked on every ray once per label (Google
// Benchmark runs a benchmark's setup again for every trial).
inline void check_packets_match_single(const KdTree& kd, const std::vector<Ray>& tiled, const std::string& label) {
  static std::mutex mutex;
  static std::set<std::string> checked;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!checked.insert(label).second) return;
  }
  std::vector<Hit> packet(tiled.size()), single(tiled.size());
  for (std::size_t i = 0; i < tiled.size(); i += kTileRays)
    kd.intersect_packet(tiled.data() + i, packet.data() + i,
                        static_cast<int>(std::min<std::size_t>(kTileRays, tiled.size() - i)));
  std::size_t hits = 0;
  for (std::size_t i = 0; i < tiled.size(); ++i) {
    single[i] = kd.intersect(tiled[i]);
    hits += single[i].valid() ? 1 : 0;
  }
  require_same_hits(packet, single, label + ": packet against single-ray hits");
  std::fprintf(stderr, "[sanity] %s: packet == single-ray on all %zu rays (%zu hits)\n", label.c_str(), tiled.size(),
               hits);
}

// One diffuse bounce from every primary hit found by `accel` (pass Lancer's kd-tree, which
// gives exactly the oracle's hits, so every program gets the same rays): origin offset
// along the normal, direction uniform in the hemisphere (not normalised).
inline std::vector<Ray> diffuse_rays(const TriangleSoA& t, const Accelerator& accel) {
  std::vector<Ray> out;
  std::uint64_t seed = 7;
  for (const Ray& r : primary_rays(t)) {
    const Hit h = accel.intersect(r);
    if (!h.valid()) continue;
    const glm::vec3 a = t.vertex(h.prim, 0);
    glm::vec3 n = glm::cross(t.vertex(h.prim, 1) - a, t.vertex(h.prim, 2) - a);
    if (glm::dot(n, r.dir) > 0.0f) n = -n;
    n = glm::normalize(n);
    Ray s;
    s.org = offset_ray_origin(r.org + h.t * r.dir, n);
    do {
      s.dir = glm::vec3(unit(seed), unit(seed), unit(seed)) * 2.0f - 1.0f;
    } while (glm::dot(s.dir, s.dir) > 1.0f || glm::dot(s.dir, s.dir) < 1e-4f);
    if (glm::dot(s.dir, n) < 0.0f) s.dir = -s.dir;
    out.push_back(s);
  }
  return out;
}

}  // namespace lancer::bench
