#include "render/ray_batch.h"

#include <stdexcept>

namespace lancer {

void trace_closest(const Accelerator& accel, std::span<const Ray> rays, TraceMode mode, tbb::task_arena& arena,
                   std::span<Hit> hits) {
  if (hits.size() != rays.size()) throw std::invalid_argument("trace_closest: not one hit slot per ray");
  for_each_ray_chunk(arena, rays.size(), [&](std::size_t first, std::size_t count) {
    if (mode == TraceMode::Packet) {
      accel.intersect_packet(rays.data() + first, hits.data() + first, static_cast<int>(count));
    } else {
      for (std::size_t i = first; i < first + count; ++i) hits[i] = accel.intersect(rays[i]);
    }
  });
}

void trace_occluded(const Accelerator& accel, std::span<const Ray> rays, TraceMode mode, tbb::task_arena& arena,
                    std::span<std::uint8_t> occluded) {
  if (occluded.size() != rays.size()) throw std::invalid_argument("trace_occluded: not one answer slot per ray");
  for_each_ray_chunk(arena, rays.size(), [&](std::size_t first, std::size_t count) {
    if (mode == TraceMode::Packet) {
      bool blocked[kRayBatchChunk];
      accel.occluded_packet(rays.data() + first, blocked, static_cast<int>(count));
      for (std::size_t i = 0; i < count; ++i) occluded[first + i] = blocked[i] ? 1 : 0;
    } else {
      for (std::size_t i = first; i < first + count; ++i) occluded[i] = accel.occluded(rays[i]) ? 1 : 0;
    }
  });
}

}  // namespace lancer
