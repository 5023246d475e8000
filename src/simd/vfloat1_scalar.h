// Width 1 as lancer::scalar's only width: the scalar reference of every width-generic
// kernel. The types and operations are vfloat1-inl.h's (the same in every ISA namespace);
// here they are visible to all of lancer::scalar.
#pragma once

#if defined(__AVX__)
// lancer::scalar is compiled with the generic (baseline) flags only; including it from an
// AVX translation unit would give the linker a second, AVX-encoded copy of its functions.
#error "vfloat1_scalar.h must not be included from a translation unit built with AVX flags."
#endif

#include "simd/isa_namespace.h"
#include "simd/vfloat1-inl.h"

namespace lancer::scalar {
using namespace width1;
}  // namespace lancer::scalar
