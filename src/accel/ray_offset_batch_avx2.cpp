// The batch origin solver for avx2: 4 doubles per vector. Built with this ISA's flags
// only (lancer_isa_sources in src/accel/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx2
#define LANCER_BATCH_LANES 4
#include "simd/vfloat8_avx2.h"
#include "accel/ray_offset_batch-inl.h"

namespace lancer::avx2 {

std::uint64_t solve_origin_lanes(const ray_offset_batch::Lanes& lanes, int count,
                                 float out[3][ray_offset_batch::kMaxLanes]) {
  return solve_origin_lanes_impl(lanes, count, out);
}

}  // namespace lancer::avx2

#endif
