// The batch surface solver for avx512: 8 doubles per vector. Built with this ISA's flags only
// (lancer_isa_sources in src/render/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA avx512
#define LANCER_BATCH_LANES 8
#include "simd/vfloat16_avx512.h"
#include "render/surface_batch-inl.h"

namespace lancer::avx512 {

std::uint64_t solve_surface_lanes(const surface_batch::Lanes& lanes, int count, surface_batch::Out& out) {
  return solve_surface_lanes_impl(lanes, count, out);
}

}  // namespace lancer::avx512

#endif
