// The per-ISA kernel tables, each defined in its own translation unit
// (kd_traverse_scalar.cpp, _sse4.cpp, _avx2.cpp, _avx512.cpp) and used only by
// select_kd_kernels. Declarations only: nothing here is compiled with ISA flags.
#pragma once

#include "accel/kd_traverse.h"

namespace lancer::scalar {
KdKernels kd_kernels();
}

#if defined(__x86_64__) || defined(_M_X64)
namespace lancer::sse4 {
KdKernels kd_kernels();
}
namespace lancer::avx2 {
KdKernels kd_kernels();
}
namespace lancer::avx512 {
KdKernels kd_kernels();
}
#endif
