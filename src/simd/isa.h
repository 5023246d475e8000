// Instruction sets Lancer has kernels for, and which of them this CPU runs.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace lancer {

// Ordered from least to most capable.
enum class Isa { Scalar, Sse4, Avx2, Avx512 };

std::string_view isa_name(Isa isa);
std::optional<Isa> parse_isa(std::string_view name);

// True when both the CPU and the operating system support the ISA
// (for AVX and AVX-512 the OS must save the wider registers: XGETBV).
bool cpu_supports(Isa isa);

// The most capable ISA this CPU supports.
Isa best_supported_isa();

// Every ISA this CPU supports, scalar first.
std::vector<Isa> supported_isas();

// Of the per-ISA versions of one batch routine (ray_offset_batch, surface_batch,
// sobol_batch), the one for `isa`: null for Isa::Scalar, where the caller runs its scalar
// code. A build without x86 kernels passes null versions, and asking it for another ISA is
// refused (`what` names the routine).
template <class Fn>
Fn isa_version(Isa isa, const char* what, Fn sse4, Fn avx2, Fn avx512) {
  const Fn f = isa == Isa::Sse4 ? sse4 : isa == Isa::Avx2 ? avx2 : isa == Isa::Avx512 ? avx512 : nullptr;
  if (!f && isa != Isa::Scalar) throw std::invalid_argument(std::string(what) + ": this build has only the scalar version");
  return f;
}

}  // namespace lancer
