// SAH kd-tree build time with a fixed thread count, plus the quality of the tree built, so
// a faster build can be checked not to give a worse tree.
//
// Names: BM_KdBuild/sah/1thread/<scene> (a oneTBB arena of one thread) and
// BM_KdBuild/sah/allthreads/<scene> (an arena of every hardware thread), wall time. Counters:
// sah_cost (compute_kd_stats), nodes and refs_per_tri of the last tree built.
#include <benchmark/benchmark.h>

#include <tbb/task_arena.h>

#include <memory>
#include <string>

#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "bench_scenes.h"

namespace {

using namespace lancer;

void bm_build_threads(benchmark::State& state, int threads, std::string name) {
  const TriangleSoA& t = bench::scene(name);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  std::unique_ptr<KdTree> kd;
  for (auto _ : state) {
    kd.reset();
    arena.execute([&] { kd = std::make_unique<KdTree>(t); });
    benchmark::DoNotOptimize(kd->nodes().data());
  }
  const KdStats st = compute_kd_stats(*kd);
  state.counters["sah_cost"] = st.sah_cost;
  state.counters["nodes"] = double(st.nodes);
  state.counters["refs_per_tri"] = double(st.references) / double(st.triangles);
  state.counters["triangles/s"] =
      benchmark::Counter(double(t.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

struct Registration {
  Registration() {
    for (const std::string& name : bench::scene_names()) {
      benchmark::RegisterBenchmark(("BM_KdBuild/sah/1thread/" + name).c_str(), bm_build_threads, 1, name)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("BM_KdBuild/sah/allthreads/" + name).c_str(), bm_build_threads, 0, name)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
} registration;

}  // namespace
