// Instruction sets Lancer has kernels for, and which of them this CPU runs.
#pragma once

#include <optional>
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

}  // namespace lancer
