#include "simd/isa.h"

#include <array>

#if defined(__x86_64__) || defined(_M_X64)
#include <cpuid.h>
#define LANCER_X86 1
#endif

namespace lancer {

namespace {

constexpr std::array<std::string_view, 4> kNames = {"scalar", "sse4", "avx2", "avx512"};

#ifdef LANCER_X86
// XCR0 says which register states the OS saves on a context switch.
unsigned long long read_xcr0() {
  unsigned eax = 0, edx = 0;
  __asm__ volatile("xgetbv" : "=a"(eax), "=d"(edx) : "c"(0));
  return (static_cast<unsigned long long>(edx) << 32) | eax;
}

struct CpuFeatures {
  bool sse42 = false, avx2 = false, fma = false, avx512 = false;
};

CpuFeatures detect() {
  CpuFeatures f;
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return f;
  f.sse42 = (c & bit_SSE4_2) != 0;
  const bool osxsave = (c & bit_OSXSAVE) != 0;
  const bool avx = (c & bit_AVX) != 0;
  f.fma = (c & bit_FMA) != 0;
  if (!osxsave || !avx) return f;
  const unsigned long long xcr0 = read_xcr0();
  const bool ymm_state = (xcr0 & 0x6) == 0x6;           // SSE and AVX state
  const bool zmm_state = (xcr0 & 0xe6) == 0xe6;         // plus opmask and ZMM state
  if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return f;
  f.avx2 = ymm_state && (b & bit_AVX2) != 0 && f.fma;
  const bool avx512 = (b & bit_AVX512F) && (b & bit_AVX512DQ) && (b & bit_AVX512BW) && (b & bit_AVX512VL);
  f.avx512 = f.avx2 && zmm_state && avx512;
  return f;
}
#endif

}  // namespace

std::string_view isa_name(Isa isa) { return kNames[static_cast<int>(isa)]; }

std::optional<Isa> parse_isa(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<Isa>(i);
  return std::nullopt;
}

bool cpu_supports(Isa isa) {
#ifdef LANCER_X86
  static const CpuFeatures f = detect();
  switch (isa) {
    case Isa::Scalar: return true;
    case Isa::Sse4: return f.sse42;
    case Isa::Avx2: return f.avx2;
    case Isa::Avx512: return f.avx512;
  }
  return false;
#else
  return isa == Isa::Scalar;
#endif
}

Isa best_supported_isa() {
  Isa best = Isa::Scalar;
  for (Isa isa : supported_isas()) best = isa;
  return best;
}

std::vector<Isa> supported_isas() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512})
    if (cpu_supports(isa)) out.push_back(isa);
  return out;
}

}  // namespace lancer
