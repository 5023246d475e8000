#include "bench_trace.h"

#include <chrono>

#include "render/ray_batch.h"

namespace lancer::bench {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

std::string lancer_call_name(Mode mode, bool occlusion) {
  if (occlusion) return mode == Mode::Packet ? "occluded_packet (64-ray chunks)" : "occluded per ray";
  return mode == Mode::Packet ? "intersect_packet (64-ray chunks)" : "intersect per ray";
}

double trace_lancer(const KdTree& kd, Mode mode, bool occlusion, std::span<const Ray> rays, tbb::task_arena& arena,
                    Answers& out) {
  const TraceMode trace_mode = mode == Mode::Packet ? TraceMode::Packet : TraceMode::Single;
  if (occlusion) {
    out.occluded.resize(rays.size());
    const auto start = Clock::now();
    trace_occluded(kd, rays, trace_mode, arena, out.occluded);
    return seconds_since(start);
  }
  out.hits.resize(rays.size());
  const auto start = Clock::now();
  trace_closest(kd, rays, trace_mode, arena, out.hits);
  return seconds_since(start);
}

double trace_embree(const EmbreeScene& scene, EmbreeCall call, std::span<const Ray> rays, tbb::task_arena& arena,
                    Answers& out) {
  if (embree_call_is_occlusion(call)) {
    out.occluded.resize(rays.size());
    std::uint8_t* answers = out.occluded.data();
    const auto start = Clock::now();
    for_each_ray_chunk(arena, rays.size(), [&](std::size_t first, std::size_t count) {
      scene.occluded(call, rays.data() + first, answers + first, count);
    });
    return seconds_since(start);
  }
  out.hits.resize(rays.size());
  Hit* hits = out.hits.data();
  const auto start = Clock::now();
  for_each_ray_chunk(arena, rays.size(), [&](std::size_t first, std::size_t count) {
    scene.intersect(call, rays.data() + first, hits + first, count);
  });
  return seconds_since(start);
}

}  // namespace lancer::bench
