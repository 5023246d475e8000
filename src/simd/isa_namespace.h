// The one macro of the SIMD layer: LANCER_ISA names the per-ISA namespace
// (scalar, sse4, avx2 or avx512) that a width-generic kernel header (*-inl.h) opens as
// `namespace lancer::LANCER_ISA { ... }`.
//
// A per-ISA translation unit defines it, includes its ISA's vector header, then the kernel
// templates, and instantiates them explicitly:
//   #define LANCER_ISA avx2
//   #include "simd/vfloat8_avx2.h"
//   #include "accel/kd_traverse-inl.h"
//   namespace lancer::avx2 { template void traverse<8>(...); }
// The vector headers refuse to compile with the wrong flags (see each header), so a TU that
// names one ISA but is built with another's flags fails to compile instead of linking.
#pragma once

#ifndef LANCER_ISA
#error "Define LANCER_ISA (scalar, sse4, avx2 or avx512) before including a *-inl.h kernel header."
#endif
