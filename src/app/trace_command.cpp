#include "app/trace_command.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "accel/accel_factory.h"
#include "app/render_command.h"
#include "render/ray_file.h"
#include "scene/load_scene.h"

namespace lancer {

namespace {

// Rays per packet in packet mode, and per parallel work item in every mode.
constexpr std::size_t kChunk = 64;

// The answers of one run: hit records, or occlusion bytes.
struct Answers {
  std::vector<HitRecord> hits;
  std::vector<std::uint8_t> occluded;
};

// Traces every ray on the arena's threads; each chunk of kChunk rays is one work item
// and writes only its own answers, so the result is the same for any thread count.
void trace_rays(const Accelerator& accel, const Scene& scene, const std::vector<Ray>& rays, const TraceOptions& opt,
                tbb::task_arena& arena, Answers& answers) {
  const std::size_t chunks = (rays.size() + kChunk - 1) / kChunk;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
      std::array<Hit, kChunk> local;
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        const std::size_t first = c * kChunk;
        const std::size_t count = std::min(kChunk, rays.size() - first);
        if (opt.occlusion) {
          for (std::size_t i = first; i < first + count; ++i) answers.occluded[i] = accel.occluded(rays[i]) ? 1 : 0;
          continue;
        }
        if (opt.mode == TraceMode::Packet) {
          accel.intersect_packet(rays.data() + first, local.data(), static_cast<int>(count));
        } else {
          for (std::size_t i = 0; i < count; ++i) local[i] = accel.intersect(rays[first + i]);
        }
        for (std::size_t i = 0; i < count; ++i)
          answers.hits[first + i] = make_hit_record(local[i], scene.source_triangle_id);
      }
    });
  });
}

}  // namespace

int run_trace(const TraceOptions& opt, std::ostream& out, std::ostream& err) {
  try {
    if (opt.threads < 0) throw std::invalid_argument("--threads must be >= 0");
    if (opt.mode != TraceMode::Packet && opt.mode != TraceMode::Single) throw std::invalid_argument("unknown --mode");
    const Isa isa = isa_from(opt.isa);
    const std::vector<Ray> rays = read_rays(opt.rays);
    const Scene scene = load_scene(opt.scene);
    print_load_warnings(scene, err);

    tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
    arena.initialize();
    std::unique_ptr<Accelerator> accel;
    arena.execute([&] { accel = make_accelerator("kdtree", scene.triangles, KdBuildOptions{}, isa); });

    Answers answers;
    if (opt.occlusion) {
      answers.occluded.resize(rays.size());
    } else {
      answers.hits.resize(rays.size());
    }
    const auto start = std::chrono::steady_clock::now();
    trace_rays(*accel, scene, rays, opt, arena, answers);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::filesystem::path parent = std::filesystem::path(opt.hits).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    std::size_t answered = 0;
    if (opt.occlusion) {
      answered = static_cast<std::size_t>(std::count(answers.occluded.begin(), answers.occluded.end(), 1));
      write_occlusion(opt.hits, answers.occluded);
    } else {
      answered = static_cast<std::size_t>(
          std::count_if(answers.hits.begin(), answers.hits.end(), [](const HitRecord& h) { return h.id != kNoHit; }));
      write_hits(opt.hits, answers.hits);
    }

    const double mrays = seconds > 0.0 ? static_cast<double>(rays.size()) / seconds * 1e-6 : 0.0;
    const int threads = arena.max_concurrency();
    char line[512];
    std::snprintf(line, sizeof line, "lancer trace: %zu rays, %s, isa %s, %d thread%s: %.3f s, %.1f Mrays/s (%zu %s)",
                  rays.size(), opt.occlusion ? "occlusion" : std::string(trace_mode_name(opt.mode)).c_str(),
                  std::string(isa_name(isa)).c_str(), threads, threads == 1 ? "" : "s", seconds, mrays, answered,
                  opt.occlusion ? "occluded" : "hits");
    out << line << "\n";
    return 0;
  } catch (const std::bad_alloc&) {
    err << "lancer: error: out of memory\n";
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace lancer
