// Embree 3 as the baseline: BVH build time (high and medium quality, one thread and the
// default thread count) and rtcIntersect1 throughput, side by side with Lancer's kd-tree on
// the same triangles and the same rays (bench_scenes.h). Embree is linked into this program
// only, never into the renderer.
//
// Names: BM_EmbreeBuild/<quality>[/1thread]/<scene>, BM_EmbreeTrace/intersect1/<rays>/<scene>
// (high-quality BVH), BM_EmbreeTrace/intersect1-medium/<rays>/<scene>, and the Lancer
// counterparts BM_LancerBuild/sah[/1thread]/<scene>, BM_LancerTrace/single/<rays>/<scene>.
// Ratios: compare the Time (build) and rays/s (trace) columns of the same run.
#include <benchmark/benchmark.h>

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <algorithm>
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

namespace {

using namespace lancer;

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

RTCBuildQuality quality_of(const std::string& q) { return q == "high" ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM; }

// The kd-tree of each scene (exactly the oracle's hits), built once: it makes the diffuse
// rays and is the reference of the sanity check.
const KdTree& lancer_tree(const std::string& name) {
  static std::map<std::string, std::unique_ptr<KdTree>> trees;
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = trees[name];
  if (!slot) slot = std::make_unique<KdTree>(bench::scene(name));
  return *slot;
}

std::vector<Ray> rays_of(const std::string& kind, const std::string& name) {
  const TriangleSoA& t = bench::scene(name);
  return kind == "primary" ? bench::primary_rays(t) : bench::diffuse_rays(t, lancer_tree(name));
}

// Embree and Lancer must find the same closest triangle on the first few thousand rays;
// they may differ only where two triangles are hit at the same distance (shared edges and
// vertices). Aborts loudly when more than 1% of the rays disagree otherwise.
void check_against_lancer(RTCScene scene, const std::string& label, const std::vector<Ray>& rays,
                          const KdTree& kd) {
  static std::mutex mutex;
  static std::set<std::string> checked;  // once per benchmark, not once per repetition
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!checked.insert(label).second) return;
  }
  const std::size_t n = std::min<std::size_t>(rays.size(), 4096);
  std::size_t ties = 0, bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Hit a = kd.intersect(rays[i]), b = embree_intersect(scene, rays[i]);
    if (a.prim == b.prim) continue;
    if (a.valid() && b.valid() && std::fabs(a.t - b.t) <= 1e-4f * std::fabs(a.t)) {
      ++ties;
    } else {
      ++bad;
    }
  }
  std::fprintf(stderr, "[sanity] %s: %zu rays, %zu ties at equal t, %zu other disagreements\n", label.c_str(), n,
               ties, bad);
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
  check_against_lancer(scene.get(), quality + "/" + kind + "/" + name, rays, lancer_tree(name));
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
    }
  }
} registration;

}  // namespace
