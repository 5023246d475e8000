// kd-tree benchmarks: build time and single-ray throughput (primary and diffuse-bounce
// rays) for SAH, middle and median trees, on procedural spheres and on the Stanford bunny
// when the shared meshes are present; plus BM_KdCost, which measures the SAH constants.
//
// Names: BM_KdBuild/<split>/<scene>, BM_KdTrace/<split>/<isa>/<rays>/<scene> and
// BM_KdCost/<isa>/spheres, for every ISA this CPU supports (scalar included).
#include <benchmark/benchmark.h>

#include <ctime>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "accel/kd_traverse.h"
#include "accel/kd_tree.h"
#include "accel/ray_offset.h"
#include "accel/watertight.h"
#include "simd/isa.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"

namespace {

using namespace lancer;

std::filesystem::path models_dir() {
  if (const char* env = std::getenv("LANCER_MODELS_DIR")) return env;
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "shared" / "scenes" / "models";
}

// Scenes are loaded once, on first use.
const TriangleSoA& scene(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Scene>();
    if (name == "bunny") {
      *slot = load_scene(models_dir() / "stanford-bunny.obj");
    } else {  // "spheres": 100k triangles of spheres of different sizes and tessellations
      append_icosphere(*slot, {0.0f, 0.0f, 0.0f}, 1.0f, 6, 0);
      append_icosphere(*slot, {2.5f, 0.0f, 0.5f}, 0.6f, 4, 0);
      append_uv_sphere(*slot, {-2.0f, 0.5f, -0.5f}, 0.8f, 96, 48, 0);
      for (int i = 0; i < 8; ++i)
        append_icosphere(*slot, {-3.0f + 0.8f * float(i), -1.8f, 0.0f}, 0.3f, 2, 0);
    }
  }
  return slot->triangles;
}

KdSplit split_of(const std::string& s) {
  return s == "middle" ? KdSplit::Middle : s == "median" ? KdSplit::Median : KdSplit::Sah;
}

std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
float unit(std::uint64_t& s) { return float(mix(s += 0x9E3779B97F4A7C15ull) >> 40) * 0x1.0p-24f; }

// A 256 x 256 pinhole camera looking at the scene's centre from 2.5 box diagonals away.
std::vector<Ray> primary_rays(const TriangleSoA& t) {
  const Bounds3 b = t.bounds();
  const glm::vec3 c = b.center(), e = b.extent();
  const float diag = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
  const glm::vec3 eye = c + glm::vec3(0.3f, 0.4f, 1.0f) * (1.2f * diag);
  const glm::vec3 fwd = glm::normalize(c - eye);
  const glm::vec3 right = glm::normalize(glm::vec3(fwd.z, 0.0f, -fwd.x));
  const glm::vec3 up = glm::vec3(right.y * fwd.z - right.z * fwd.y, right.z * fwd.x - right.x * fwd.z,
                                 right.x * fwd.y - right.y * fwd.x);
  const int n = 256;
  std::vector<Ray> rays;
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

// One diffuse bounce from every primary hit: origin offset along the normal, direction
// uniform in the hemisphere.
std::vector<Ray> diffuse_rays(const TriangleSoA& t, const KdTree& kd) {
  std::vector<Ray> out;
  std::uint64_t seed = 7;
  for (const Ray& r : primary_rays(t)) {
    const Hit h = kd.intersect(r);
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

void bm_build(benchmark::State& state, std::string split, std::string name) {
  const TriangleSoA& t = scene(name);
  KdBuildOptions o;
  o.split = split_of(split);
  for (auto _ : state) {
    KdTree kd(t, o);
    benchmark::DoNotOptimize(kd.nodes().data());
  }
  state.counters["triangles/s"] =
      benchmark::Counter(double(t.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void bm_trace(benchmark::State& state, std::string split, Isa isa, std::string kind, std::string name) {
  const TriangleSoA& t = scene(name);
  KdBuildOptions o;
  o.split = split_of(split);
  const KdTree kd(t, o, isa);
  const std::vector<Ray> rays = kind == "primary" ? primary_rays(t) : diffuse_rays(t, kd);
  std::int64_t n = 0;
  for (auto _ : state) {
    for (const Ray& r : rays) benchmark::DoNotOptimize(kd.intersect(r));
    n += static_cast<std::int64_t>(rays.size());
  }
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
}

// Thread CPU time: the development machine is shared, and wall time would count the
// time other processes hold the core.
double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The SAH constants (see kd_build_cost.h), measured in place: trees built with several
// cost ratios do different mixes of work on the same diffuse rays. For each tree the CPU
// time per ray T, the inner-node steps S and the triangle tests I per ray (counted with
// kd_intersect_counted) are recorded, and T = c + C_trav * S + C_isect * I is fitted by
// least squares (c: the per-ray setup). Cache misses on nodes and on leaf triangles are
// thereby charged to the operation that causes them.
void bm_cost(benchmark::State& state, Isa isa) {
  const TriangleSoA& t = scene("spheres");
  const std::vector<Ray> rays = diffuse_rays(t, KdTree(t));
  const float ratios[] = {0.25f, 0.5f, 1.0f, 2.0f, 4.0f, 8.0f};
  std::vector<std::unique_ptr<KdTree>> trees;
  std::vector<double> steps, tests;
  for (float ratio : ratios) {
    KdBuildOptions o;
    o.traversal_cost = 1.0f;
    o.intersection_cost = ratio;
    trees.push_back(std::make_unique<KdTree>(t, o, isa));
    KdTraversalCounts counts;
    for (const Ray& r : rays) trees.back()->intersect_counted(r, counts);
    steps.push_back(double(counts.inner_steps) / double(rays.size()));
    tests.push_back(double(counts.triangle_tests) / double(rays.size()));
  }
  std::vector<double> best_ns(trees.size(), 1e300);
  for (auto _ : state) {
    for (std::size_t k = 0; k < trees.size(); ++k) {
      const KdTree& kd = *trees[k];
      const double start = cpu_seconds();
      for (const Ray& r : rays) benchmark::DoNotOptimize(kd.intersect(r));
      best_ns[k] = std::min(best_ns[k], 1e9 * (cpu_seconds() - start) / double(rays.size()));
    }
  }
  // Normal equations of the 3-parameter least-squares fit, solved by Cramer's rule.
  double m[3][3] = {}, rhs[3] = {};
  for (std::size_t k = 0; k < trees.size(); ++k) {
    const double x[3] = {1.0, steps[k], tests[k]};
    for (int i = 0; i < 3; ++i) {
      rhs[i] += x[i] * best_ns[k];
      for (int j = 0; j < 3; ++j) m[i][j] += x[i] * x[j];
    }
  }
  auto det3 = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  double coef[3];
  for (int c = 0; c < 3; ++c) {
    double mc[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) mc[i][j] = j == c ? rhs[i] : m[i][j];
    coef[c] = det3(mc) / det3(m);
  }
  state.counters["ns_per_ray_setup"] = coef[0];
  state.counters["ns_per_step"] = coef[1];
  state.counters["ns_per_test"] = coef[2];
  state.counters["isect_over_trav"] = coef[2] / coef[1];
  for (std::size_t k = 0; k < trees.size(); ++k) {
    // Raw data per tree (tree k was built with C_isect / C_trav = ratios[k]).
    char tag[32];
    std::snprintf(tag, sizeof tag, "r%zu_ns", k);
    state.counters[tag] = best_ns[k];
    std::snprintf(tag, sizeof tag, "r%zu_steps", k);
    state.counters[tag] = steps[k];
    std::snprintf(tag, sizeof tag, "r%zu_tests", k);
    state.counters[tag] = tests[k];
  }
}

struct Registration {
  Registration() {
    std::vector<std::string> scenes{"spheres"};
    if (std::filesystem::exists(models_dir() / "stanford-bunny.obj")) scenes.push_back("bunny");
    for (const std::string& name : scenes)
      for (const char* split : {"sah", "middle", "median"}) {
        benchmark::RegisterBenchmark(("BM_KdBuild/" + std::string(split) + "/" + name).c_str(), bm_build, split, name)
            ->Unit(benchmark::kMillisecond);
        for (Isa isa : supported_isas())
          for (const char* kind : {"primary", "diffuse"}) {
            const std::string bm = "BM_KdTrace/" + std::string(split) + "/" + std::string(isa_name(isa)) + "/" + kind +
                                   "/" + name;
            benchmark::RegisterBenchmark(bm.c_str(), bm_trace, split, isa, kind, name)->Unit(benchmark::kMillisecond);
          }
      }
    for (Isa isa : supported_isas())
      benchmark::RegisterBenchmark(("BM_KdCost/" + std::string(isa_name(isa)) + "/spheres").c_str(), bm_cost, isa)
          ->Iterations(5)
          ->Unit(benchmark::kMillisecond);
  }
} registration;

}  // namespace
