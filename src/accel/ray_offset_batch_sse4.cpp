// The batch origin solver for sse4: 2 doubles per vector. Built with this ISA's flags
// only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA sse4
#define LANCER_BATCH_LANES 2
#include "simd/vfloat4_sse4.h"
#include "accel/ray_offset_batch-inl.h"

namespace lancer::sse4 {

std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]) {
  return solve_origin_lanes_impl(lanes, count, out);
}

}  // namespace lancer::sse4

#endif
