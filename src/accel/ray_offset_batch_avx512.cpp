// The batch origin solver for avx512: 8 doubles per vector. Built with this ISA's flags
// only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx512
#define LANCER_BATCH_LANES 8
#include "simd/vfloat16_avx512.h"
#include "accel/ray_offset_batch-inl.h"

namespace lancer::avx512 {

std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]) {
  return solve_origin_lanes_impl(lanes, count, out);
}

}  // namespace lancer::avx512

#endif
