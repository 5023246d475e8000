#include "app/trace_command.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <tbb/task_arena.h>

#include "accel/accel_factory.h"
#include "accel/kd_stats.h"
#include "accel/kd_tree.h"
#include "app/render_command.h"
#include "render/ray_batch.h"
#include "render/ray_file.h"
#include "scene/load_scene.h"
#include "simd/out_of_memory.h"

namespace lancer {

int run_trace(const TraceOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    if (opt.threads < 0) throw std::invalid_argument("--threads must be >= 0");
    if (opt.mode != TraceMode::Packet && opt.mode != TraceMode::Single) throw std::invalid_argument("unknown --mode");
    const Isa isa = isa_from(opt.isa);
    const std::vector<Ray> rays = read_rays(opt.rays);
    const Scene scene = load_scene(opt.scene, std::nullopt, std::nullopt, opt.instancing);
    print_load_warnings(scene, err);

    tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
    arena.initialize();
    std::unique_ptr<Accelerator> accel;
    arena.execute([&] { accel = make_accelerator("kdtree", scene.triangles, scene.instancing, KdBuildOptions{}, isa); });

    // The timed part is the tracing alone (render/ray_batch.h); turning hits into records is not.
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    const auto start = std::chrono::steady_clock::now();
    if (opt.occlusion) {
      occluded.resize(rays.size());
      trace_occluded(*accel, rays, opt.mode, arena, occluded);
    } else {
      hits.resize(rays.size());
      trace_closest(*accel, rays, opt.mode, arena, hits);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::filesystem::path parent = std::filesystem::path(opt.hits).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    std::size_t answered = 0;
    if (opt.occlusion) {
      answered = static_cast<std::size_t>(std::count(occluded.begin(), occluded.end(), 1));
      write_occlusion(opt.hits, occluded);
    } else {
      std::vector<HitRecord> records(hits.size());
      for (std::size_t i = 0; i < hits.size(); ++i)
        records[i] = hits[i].valid() ? HitRecord{hits[i].t, scene.source_id(hits[i].prim, hits[i].instance)}
                                     : make_hit_record(hits[i], scene.source_triangle_id);
      answered = static_cast<std::size_t>(
          std::count_if(records.begin(), records.end(), [](const HitRecord& h) { return h.id != kNoHit; }));
      write_hits(opt.hits, records);
    }

    const double mrays = seconds > 0.0 ? static_cast<double>(rays.size()) / seconds * 1e-6 : 0.0;
    const int threads = arena.max_concurrency();
    char line[512];
    std::snprintf(line, sizeof line, "lancer trace: %zu rays, %s, isa %s, %d thread%s: %.3f s, %.1f Mrays/s (%zu %s)",
                  rays.size(), opt.occlusion ? "occlusion" : std::string(trace_mode_name(opt.mode)).c_str(),
                  std::string(isa_name(isa)).c_str(), threads, threads == 1 ? "" : "s", seconds, mrays, answered,
                  opt.occlusion ? "occluded" : "hits");
    out << line << "\n";
    // What the time bought, counted in a second, untimed pass (the same for every mode).
    if (const auto* kd = dynamic_cast<const KdTree*>(accel.get())) {
      KdWorkPerRay w;
      arena.execute([&] { w = measure_kd_work(*kd, rays, opt.occlusion); });
      std::snprintf(line, sizeof line,
                    "lancer trace: single-ray kernel work per ray: %.2f inner steps, %.2f leaves, %.2f triangle tests",
                    w.inner_steps, w.leaves, w.triangle_tests);
      out << line << "\n";
    }
    return 0;
  } catch (const std::bad_alloc& e) {
    err << "lancer: error: " << out_of_memory_message(e) << "\n";
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace lancer
