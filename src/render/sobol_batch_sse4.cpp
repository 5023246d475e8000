// The batch Sobol' draw for sse4: 2 samplers per vector. Built with this ISA's flags only
// (lancer_isa_sources in src/render/CMakeLists.txt); elsewhere it is empty.
#if defined(__x86_64__) || defined(_M_X64)

#define LANCER_ISA sse4
#define LANCER_SOBOL_LANES 2
#include "simd/vfloat4_sse4.h"
#include "render/sobol_batch-inl.h"

namespace lancer::sse4 {

void draw_sobol_lanes(const sobol_batch::Lanes& lanes, int count, sobol_batch::Out& out) {
  draw_sobol_lanes_impl(lanes, count, out);
}

}  // namespace lancer::sse4

#endif
