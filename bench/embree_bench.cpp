// Embree 3 as the baseline: BVH build time (high and medium quality, one thread and the
// default thread count) and trace throughput, side by side with Lancer's kd-tree on the
// same triangles and the same rays (bench_scenes.h). Embree is linked into this program
// only, never into the renderer.
//
// Names: BM_EmbreeBuild/<quality>[/1thread]/<scene>, BM_EmbreeTrace/intersect1/<rays>/<scene>
// (high-quality BVH), BM_EmbreeTrace/intersect1-medium/<rays>/<scene>, and the Lancer
// counterparts BM_LancerBuild/sah[/1thread]/<scene>, BM_LancerTrace/single/<rays>/<scene>.
//
// Packets, on the primary rays in 8x8 pixel tiles of 64 rays (bench::tiled_primary_rays),
// <threads> = 1thread (a plain loop over the tiles) or allthreads (tbb::parallel_for over
// the tiles in the default arena, bench::for_each_tile):
//   BM_EmbreeTrace/intersect16/primary/<threads>/<scene>     4 rtcIntersect16 calls per tile
//                                                            (two tile rows each)
//   BM_EmbreeTrace/intersect8/primary/<threads>/<scene>      8 rtcIntersect8 calls per tile
//                                                            (one tile row each)
//   BM_EmbreeTrace/intersect1-tiled/primary/<threads>/<scene> rtcIntersect1 per ray, tile order
//   BM_LancerTrace/packet/<isa>/primary/<threads>/<scene>     KdTree::intersect_packet per tile
//   BM_LancerTrace/single/<isa>/primary-tiled/<threads>/<scene> KdTree::intersect per ray
// with <isa> = best_supported_isa(). Embree picks its own ISA (Embree 3 has no API to ask
// which; the start-up line prints whether it has native 4/8/16-wide packets).
//
// The Embree scene of every trace row is the same: built by a device with the default
// thread count (the build is not timed), RTC_BUILD_QUALITY_HIGH for the scene and the
// geometry (intersect1-medium: MEDIUM), default scene flags (RTC_SCENE_FLAG_NONE: no
// RTC_SCENE_FLAG_ROBUST) and a default intersect context (RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT).
// Embree traces on the calling thread only, so a plain loop is one thread. Every trace
// converts Lancer's Ray to Embree's layout and the result back to Hit inside the timed loop,
// as Lancer's rows take Ray and give Hit.
//
// Checks: every Embree row compares its hits with Lancer's kd-tree on all its rays
// (check_against_lancer), the Lancer packet rows require exactly the single-ray hits
// (bench::check_packets_match_single), and every tiled row requires the timed loop to leave
// the hits of an untimed one-thread pass. Any failure aborts the program.
// Counters: rays/s (a rate: wall-clock time on the allthreads rows, CPU time on the others)
// and threads on the tiled rows. Compare the Time (build) and rays/s (trace) columns of the
// same run.
#include <benchmark/benchmark.h>

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_scenes.h"
#include "simd/isa.h"

namespace {

using namespace lancer;
using bench::Threads;

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "lancer_bench_embree: %s\n", what.c_str());
  std::abort();
}

void on_embree_error(void*, RTCError code, const char* message) {
  die("Embree error " + std::to_string(int(code)) + ": " + (message ? message : "(no message)"));
}

struct DeviceDeleter {
  void operator()(RTCDeviceTy* d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCSceneTy* s) const { rtcReleaseScene(s); }
};
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneDeleter>;

// threads = 0: Embree's default (every hardware thread).
DevicePtr make_device(int threads) {
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
  RTCDevice d = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (!d) die("rtcNewDevice(\"" + config + "\") failed");
  rtcSetDeviceErrorFunction(d, on_embree_error, nullptr);
  return DevicePtr(d);
}

// Once per program: Embree's version and which packet widths it runs natively.
void print_embree_info(RTCDevice d) {
  static std::once_flag once;
  std::call_once(once, [d] {
    std::fprintf(stderr,
                 "[embree] version %zd; picks its own ISA (Embree 3 cannot report it); native packets: "
                 "ray4 %zd, ray8 %zd, ray16 %zd; Lancer's rows use %s\n",
                 rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION),
                 rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED),
                 rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED),
                 rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED),
                 std::string(isa_name(best_supported_isa())).c_str());
  });
}

// One triangle geometry holding copies of the triangles (Embree wants float3 vertices;
// TriangleSoA is structure-of-arrays), so Embree's primitive IDs are Lancer's indices.
// Everything from the SoA to a committed scene counts as build time, like KdTree(tris).
ScenePtr build_scene(RTCDevice device, const TriangleSoA& t, RTCBuildQuality quality) {
  ScenePtr scene(rtcNewScene(device));
  rtcSetSceneBuildQuality(scene.get(), quality);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(g, quality);
  const std::size_t n = t.size();
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* idx = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), n));
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      float* p = v + 3 * (3 * i + k);
      p[0] = t.x[k][i];
      p[1] = t.y[k][i];
      p[2] = t.z[k][i];
      idx[3 * i + k] = static_cast<std::uint32_t>(3 * i + k);
    }
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene.get(), g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene.get());
  return scene;
}

Hit embree_intersect(RTCScene scene, const Ray& r) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = r.org.x;
  rh.ray.org_y = r.org.y;
  rh.ray.org_z = r.org.z;
  rh.ray.tnear = r.tnear;
  rh.ray.dir_x = r.dir.x;
  rh.ray.dir_y = r.dir.y;
  rh.ray.dir_z = r.dir.z;
  rh.ray.time = 0.0f;
  rh.ray.tfar = r.tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.prim = rh.hit.primID;
  h.u = rh.hit.u;
  h.v = rh.hit.v;
  return h;
}

// Embree's packet types and calls by width.
template <int K>
struct EmbreePacket;
template <>
struct EmbreePacket<8> {
  using RayHit = RTCRayHit8;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
    rtcIntersect8(valid, s, c, rh);
  }
};
template <>
struct EmbreePacket<16> {
  using RayHit = RTCRayHit16;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* rh) {
    rtcIntersect16(valid, s, c, rh);
  }
};

// Every lane active; rtcIntersect16 wants the mask aligned like the packet (64 bytes).
alignas(64) constexpr std::array<int, 16> kAllValid = [] {
  std::array<int, 16> a{};
  a.fill(-1);
  return a;
}();

// Traces rays[0..K) with one rtcIntersectK call.
template <int K>
void embree_intersect_packet(RTCScene scene, const Ray* rays, Hit* hits) {
  using RayHit = typename EmbreePacket<K>::RayHit;
  static_assert(alignof(RayHit) >= 4 * K, "Embree wants a K-ray packet aligned to 4K bytes");
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RayHit rh;
  for (int i = 0; i < K; ++i) {
    const Ray& r = rays[i];
    rh.ray.org_x[i] = r.org.x;
    rh.ray.org_y[i] = r.org.y;
    rh.ray.org_z[i] = r.org.z;
    rh.ray.tnear[i] = r.tnear;
    rh.ray.dir_x[i] = r.dir.x;
    rh.ray.dir_y[i] = r.dir.y;
    rh.ray.dir_z[i] = r.dir.z;
    rh.ray.time[i] = 0.0f;
    rh.ray.tfar[i] = r.tfar;
    rh.ray.mask[i] = 0xFFFFFFFFu;
    rh.ray.id[i] = static_cast<unsigned>(i);
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
  }
  EmbreePacket<K>::intersect(kAllValid.data(), scene, &context, &rh);
  for (int i = 0; i < K; ++i) {
    Hit h;
    if (rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID) {
      h.t = rh.ray.tfar[i];
      h.prim = rh.hit.primID[i];
      h.u = rh.hit.u[i];
      h.v = rh.hit.v[i];
    }
    hits[i] = h;
  }
}

enum class EmbreeCall { Intersect16, Intersect8, Intersect1 };

const char* call_name(EmbreeCall call) {
  return call == EmbreeCall::Intersect16  ? "intersect16"
         : call == EmbreeCall::Intersect8 ? "intersect8"
                                          : "intersect1-tiled";
}

// One 8x8 tile: rows of the tile per packet call (tiled_primary_rays keeps them in row order).
void embree_trace_tile(EmbreeCall call, RTCScene scene, const Ray* rays, Hit* hits) {
  static_assert(bench::kTileRays % 16 == 0 && bench::kTileSize == 8);
  switch (call) {
    case EmbreeCall::Intersect16:
      for (int k = 0; k < bench::kTileRays; k += 16) embree_intersect_packet<16>(scene, rays + k, hits + k);
      break;
    case EmbreeCall::Intersect8:
      for (int k = 0; k < bench::kTileRays; k += 8) embree_intersect_packet<8>(scene, rays + k, hits + k);
      break;
    case EmbreeCall::Intersect1:
      for (int k = 0; k < bench::kTileRays; ++k) hits[k] = embree_intersect(scene, rays[k]);
      break;
  }
}

RTCBuildQuality quality_of(const std::string& q) { return q == "high" ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM; }

// The kd-tree of each scene (exactly the oracle's hits), built once for the best ISA: it
// makes the diffuse rays, is the reference of the sanity check and runs Lancer's rows.
const KdTree& lancer_tree(const std::string& name) {
  static std::map<std::string, std::unique_ptr<KdTree>> trees;
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = trees[name];
  if (!slot) slot = std::make_unique<KdTree>(bench::scene(name), KdBuildOptions{}, best_supported_isa());
  return *slot;
}

std::vector<Ray> rays_of(const std::string& kind, const std::string& name) {
  const TriangleSoA& t = bench::scene(name);
  return kind == "primary" ? bench::primary_rays(t) : bench::diffuse_rays(t, lancer_tree(name));
}

// Embree's hits (embree_hits[i] for rays[i]) and Lancer's must be on the same closest
// triangle; they may differ only where two triangles are hit at the same distance (shared
// edges and vertices). Checked on every ray, once per label; aborts loudly when more than
// 1% of the rays disagree otherwise.
void check_against_lancer(const std::string& label, const std::vector<Ray>& rays, const std::vector<Hit>& embree_hits,
                          const KdTree& kd) {
  static std::mutex mutex;
  static std::set<std::string> checked;  // once per benchmark, not once per repetition
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!checked.insert(label).second) return;
  }
  if (embree_hits.size() != rays.size()) die(label + ": not one Embree hit per ray");
  const std::size_t n = rays.size();
  std::size_t hits = 0, ties = 0, bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Hit a = kd.intersect(rays[i]), &b = embree_hits[i];
    hits += a.valid() ? 1 : 0;
    if (a.prim == b.prim) continue;
    if (a.valid() && b.valid() && std::fabs(a.t - b.t) <= 1e-4f * std::fabs(a.t)) {
      ++ties;
    } else {
      ++bad;
    }
  }
  std::fprintf(stderr, "[sanity] %s: %zu rays (%zu hit), %zu ties at equal t, %zu other disagreements\n",
               label.c_str(), n, hits, ties, bad);
  if (bad * 100 > n) die(label + ": Embree and Lancer disagree on " + std::to_string(bad) + " of " +
                         std::to_string(n) + " rays: the benchmarks do not trace the same scene");
}

void bm_embree_build(benchmark::State& state, std::string quality, int threads, std::string name) {
  const TriangleSoA& t = bench::scene(name);
  const DevicePtr device = make_device(threads);
  for (auto _ : state) {
    ScenePtr scene = build_scene(device.get(), t, quality_of(quality));
    benchmark::DoNotOptimize(scene.get());
  }
  state.counters["triangles/s"] =
      benchmark::Counter(double(t.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void bm_lancer_build(benchmark::State& state, int threads, std::string name) {
  const TriangleSoA& t = bench::scene(name);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  for (auto _ : state) {
    arena.execute([&] {
      KdTree kd(t);
      benchmark::DoNotOptimize(kd.nodes().data());
    });
  }
  state.counters["triangles/s"] =
      benchmark::Counter(double(t.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void bm_embree_trace(benchmark::State& state, std::string quality, std::string kind, std::string name) {
  const DevicePtr device = make_device(0);
  const ScenePtr scene = build_scene(device.get(), bench::scene(name), quality_of(quality));
  const std::vector<Ray> rays = rays_of(kind, name);
  std::vector<Hit> embree_hits(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) embree_hits[i] = embree_intersect(scene.get(), rays[i]);
  check_against_lancer(quality + "/" + kind + "/" + name, rays, embree_hits, lancer_tree(name));
  std::int64_t n = 0;
  for (auto _ : state) {
    for (const Ray& r : rays) benchmark::DoNotOptimize(embree_intersect(scene.get(), r));
    n += static_cast<std::int64_t>(rays.size());
  }
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
}

void bm_lancer_trace(benchmark::State& state, std::string kind, std::string name) {
  const KdTree& kd = lancer_tree(name);
  const std::vector<Ray> rays = rays_of(kind, name);
  std::int64_t n = 0;
  for (auto _ : state) {
    for (const Ray& r : rays) benchmark::DoNotOptimize(kd.intersect(r));
    n += static_cast<std::int64_t>(rays.size());
  }
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
}

// The tiled rows' timed loop: trace_tile(i) for every tile, on `threads`; the hits must
// stay those of an untimed one-thread pass (`expected`).
template <class TraceTile>
void time_tiles(benchmark::State& state, Threads threads, std::size_t tiles, const TraceTile& trace_tile,
                const std::vector<Hit>& hits, const std::vector<Hit>& expected, const std::string& label) {
  std::int64_t n = 0;
  for (auto _ : state) {
    bench::for_each_tile(threads, tiles, trace_tile);
    benchmark::DoNotOptimize(hits.data());
    benchmark::ClobberMemory();
    n += static_cast<std::int64_t>(hits.size());
  }
  bench::require_same_hits(hits, expected, label + ": hits of the timed loop");
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["threads"] = double(bench::thread_count(threads));
}

std::string embree_tiled_name(EmbreeCall call, Threads threads, const std::string& name, int image) {
  return std::string("BM_EmbreeTrace/") + call_name(call) + "/" + bench::primary_set_name(image) + "/" +
         bench::threads_name(threads) + "/" + name;
}

void bm_embree_tiled(benchmark::State& state, EmbreeCall call, Threads threads, std::string name, int image) {
  const DevicePtr device = make_device(0);
  print_embree_info(device.get());
  const ScenePtr scene = build_scene(device.get(), bench::scene(name), RTC_BUILD_QUALITY_HIGH);
  const std::vector<Ray> rays = bench::tiled_primary_rays(bench::scene(name), image);
  const std::size_t tiles = rays.size() / bench::kTileRays;
  std::vector<Hit> hits(rays.size());
  const auto trace_tile = [&](std::size_t tile) {
    const std::size_t first = tile * bench::kTileRays;
    embree_trace_tile(call, scene.get(), rays.data() + first, hits.data() + first);
  };
  bench::for_each_tile(Threads::One, tiles, trace_tile);
  const std::vector<Hit> expected = hits;
  check_against_lancer(std::string("high/") + call_name(call) + "/" + bench::primary_set_name(image) + "-tiled/" + name,
                       rays, expected, lancer_tree(name));
  time_tiles(state, threads, tiles, trace_tile, hits, expected, embree_tiled_name(call, threads, name, image));
}

std::string lancer_tiled_name(bool packet, Threads threads, const std::string& name, int image) {
  const std::string isa(isa_name(best_supported_isa()));
  return std::string("BM_LancerTrace/") + (packet ? "packet/" : "single/") + isa + "/" +
         bench::primary_set_name(image) + (packet ? "/" : "-tiled/") + bench::threads_name(threads) + "/" + name;
}

void bm_lancer_tiled(benchmark::State& state, bool packet, Threads threads, std::string name, int image) {
  const KdTree& kd = lancer_tree(name);
  const std::vector<Ray> rays = bench::tiled_primary_rays(bench::scene(name), image);
  const std::size_t tiles = rays.size() / bench::kTileRays;
  const std::string label = lancer_tiled_name(packet, threads, name, image);
  if (packet) bench::check_packets_match_single(kd, rays, label);
  std::vector<Hit> hits(rays.size());
  const auto trace_tile = [&](std::size_t tile) {
    const std::size_t first = tile * bench::kTileRays;
    if (packet) {
      kd.intersect_packet(rays.data() + first, hits.data() + first, bench::kTileRays);
    } else {
      for (std::size_t k = first; k < first + bench::kTileRays; ++k) hits[k] = kd.intersect(rays[k]);
    }
  };
  bench::for_each_tile(Threads::One, tiles, trace_tile);
  const std::vector<Hit> expected = hits;
  time_tiles(state, threads, tiles, trace_tile, hits, expected, label);
}

struct Registration {
  Registration() {
    using benchmark::RegisterBenchmark;
    for (const std::string& name : bench::scene_names()) {
      for (const char* q : {"high", "medium"}) {
        const std::string quality = q;
        RegisterBenchmark(("BM_EmbreeBuild/" + quality + "/" + name).c_str(), bm_embree_build, quality, 0, name)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        RegisterBenchmark(("BM_EmbreeBuild/" + quality + "/1thread/" + name).c_str(), bm_embree_build, quality, 1,
                          name)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
      RegisterBenchmark(("BM_LancerBuild/sah/" + name).c_str(), bm_lancer_build, 0, name)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      RegisterBenchmark(("BM_LancerBuild/sah/1thread/" + name).c_str(), bm_lancer_build, 1, name)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      for (const char* k : {"primary", "diffuse"}) {
        const std::string kind = k;
        RegisterBenchmark(("BM_EmbreeTrace/intersect1/" + kind + "/" + name).c_str(), bm_embree_trace,
                          std::string("high"), kind, name)
            ->Unit(benchmark::kMillisecond);
        RegisterBenchmark(("BM_EmbreeTrace/intersect1-medium/" + kind + "/" + name).c_str(), bm_embree_trace,
                          std::string("medium"), kind, name)
            ->Unit(benchmark::kMillisecond);
        RegisterBenchmark(("BM_LancerTrace/single/" + kind + "/" + name).c_str(), bm_lancer_trace, kind, name)
            ->Unit(benchmark::kMillisecond);
      }
      for (const int image : {bench::kImageSize, 1024})
        for (const Threads threads : {Threads::One, Threads::All}) {
          std::vector<benchmark::internal::Benchmark*> rows;
          for (const EmbreeCall call : {EmbreeCall::Intersect16, EmbreeCall::Intersect8, EmbreeCall::Intersect1})
            rows.push_back(RegisterBenchmark(embree_tiled_name(call, threads, name, image).c_str(), bm_embree_tiled,
                                             call, threads, name, image));
          for (const bool packet : {true, false})
            rows.push_back(RegisterBenchmark(lancer_tiled_name(packet, threads, name, image).c_str(),
                                             bm_lancer_tiled, packet, threads, name, image));
          for (auto* row : rows) {
            row->Unit(benchmark::kMillisecond);
            if (threads == Threads::All) row->UseRealTime();
          }
        }
    }
  }
} registration;

}  // namespace
