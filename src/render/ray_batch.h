// Tracing a whole batch of rays (a ray file, a ray set) on a task arena's threads, the way
// `lancer trace` and `lancer-bench` both time it: consecutive chunks of kRayBatchChunk rays,
// one chunk per work item, each writing only its own answers, so the answers never depend
// on the thread count.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "accel/accelerator.h"
#include "render/render_settings.h"

namespace lancer {

// Rays per chunk: one packet in packet mode (an 8x8 pixel tile of a tile-ordered ray set).
inline constexpr std::size_t kRayBatchChunk = 64;

// Calls trace_chunk(first, count) once for each chunk [first, first + count) of [0, rays),
// count = kRayBatchChunk except for the last, in parallel on `arena`'s threads.
template <class TraceChunk>
void for_each_ray_chunk(tbb::task_arena& arena, std::size_t rays, const TraceChunk& trace_chunk) {
  const std::size_t chunks = (rays + kRayBatchChunk - 1) / kRayBatchChunk;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        const std::size_t first = c * kRayBatchChunk;
        trace_chunk(first, std::min(kRayBatchChunk, rays - first));
      }
    });
  });
}

// Closest hits of every ray into hits[i] (hits.size() must equal rays.size()): Packet mode
// hands each chunk to one Accelerator::intersect_packet call, Single mode calls
// Accelerator::intersect per ray. Both give the same hits.
void trace_closest(const Accelerator& accel, std::span<const Ray> rays, TraceMode mode, tbb::task_arena& arena,
                   std::span<Hit> hits);

// occluded[i] = 1 when rays[i] is blocked, else 0 (sizes must match): Packet mode hands
// each chunk to one Accelerator::occluded_packet call (lanes leave at their first hit),
// Single mode calls Accelerator::occluded per ray. Both give the same answers.
void trace_occluded(const Accelerator& accel, std::span<const Ray> rays, TraceMode mode, tbb::task_arena& arena,
                    std::span<std::uint8_t> occluded);

}  // namespace lancer
