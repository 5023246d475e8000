#include "simd/isa.h"

#include <gtest/gtest.h>

namespace lancer {
namespace {

TEST(Isa, NamesRoundTrip) {
  for (Isa isa : {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512}) {
    const auto parsed = parse_isa(isa_name(isa));
    ASSERT_TRUE(parsed.has_value()) << isa_name(isa);
    EXPECT_EQ(*parsed, isa);
  }
  EXPECT_FALSE(parse_isa("avx3").has_value());
  EXPECT_FALSE(parse_isa("").has_value());
}

TEST(Isa, SupportedListIsOrderedAndConsistent) {
  const auto isas = supported_isas();
  ASSERT_FALSE(isas.empty());
  EXPECT_EQ(isas.front(), Isa::Scalar);
  for (std::size_t i = 1; i < isas.size(); ++i) EXPECT_LT(isas[i - 1], isas[i]);
  EXPECT_EQ(best_supported_isa(), isas.back());
  for (Isa isa : isas) EXPECT_TRUE(cpu_supports(isa));
}

// Each ISA implies the ones below it: a CPU with AVX-512 kernels also runs AVX2 and SSE4.
TEST(Isa, SupportIsMonotonic) {
  bool below = true;
  for (Isa isa : {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512}) {
    if (!below) {
      EXPECT_FALSE(cpu_supports(isa)) << isa_name(isa);
    }
    below = below && cpu_supports(isa);
  }
}

#if defined(__x86_64__)
// Cross-check our cpuid/XGETBV decoding with the compiler's own detection.
TEST(Isa, AgreesWithCompilerBuiltins) {
  __builtin_cpu_init();
  EXPECT_EQ(cpu_supports(Isa::Sse4), static_cast<bool>(__builtin_cpu_supports("sse4.2")));
  if (cpu_supports(Isa::Avx2)) {
    EXPECT_TRUE(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"));
  }
  if (cpu_supports(Isa::Avx512)) {
    EXPECT_TRUE(__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw"));
  }
}
#endif

}  // namespace
}  // namespace lancer
