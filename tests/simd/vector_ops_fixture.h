// GoogleTest side of the vector-op tests: one fixture parameterised over every ISA, which
// skips (with a message) before touching an ISA the CPU lacks, and helpers that compute
// expected values with the scalar (width 1) table, lane by lane. Generic flags only.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "simd/isa.h"
#include "vector_ops_table.h"

namespace lancer {
// Test names and failure messages show "avx2", not the enum's bytes.
inline void PrintTo(Isa isa, std::ostream* os) { *os << isa_name(isa); }
}  // namespace lancer

namespace lancer::test {

// nullptr when this build has no kernels for the ISA (x86 ISAs on other machines).
inline const VectorOpsTable* vector_ops_for(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return &scalar::test::kVectorOps;
#if defined(__x86_64__) || defined(_M_X64)
    case Isa::Sse4: return &sse4::test::kVectorOps;
    case Isa::Avx2: return &avx2::test::kVectorOps;
    case Isa::Avx512: return &avx512::test::kVectorOps;
#else
    default: return nullptr;
#endif
  }
  return nullptr;
}

inline const std::vector<Isa>& all_isas() {
  static const std::vector<Isa> isas = {Isa::Scalar, Isa::Sse4, Isa::Avx2, Isa::Avx512};
  return isas;
}

inline std::string isa_param_name(const ::testing::TestParamInfo<Isa>& info) {
  return std::string(isa_name(info.param));
}

class VectorOpsTest : public ::testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    const Isa isa = GetParam();
    if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU does not support " << isa_name(isa);
    ops_ = vector_ops_for(isa);
    if (ops_ == nullptr) GTEST_SKIP() << isa_name(isa) << " kernels are not built for this architecture";
  }

  const VectorOpsTable& ops() const { return *ops_; }
  static const VectorOpsTable& scalar() { return scalar::test::kVectorOps; }
  int width() const { return ops_->width; }
  Isa isa() const { return GetParam(); }
  bool has_fma() const { return isa() != Isa::Sse4; }

 private:
  const VectorOpsTable* ops_ = nullptr;
};

// Lane counts used by the tests: a multiple of every width.
inline constexpr int kLanes = 1024;

inline std::vector<float> random_floats(int count, std::uint32_t seed, float lo, float hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> out(count);
  for (float& x : out) x = dist(rng);
  return out;
}

inline std::vector<std::int32_t> random_ints(int count, std::uint32_t seed, std::int32_t lo, std::int32_t hi) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::int32_t> dist(lo, hi);
  std::vector<std::int32_t> out(count);
  for (std::int32_t& x : out) x = dist(rng);
  return out;
}

inline std::vector<std::int32_t> random_mask(int count, std::uint32_t seed) { return random_ints(count, seed, 0, 1); }

// Values every float test must survive: NaN, infinities, signed zeros, extremes, denormals.
inline std::vector<float> special_floats() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  return {nan, -nan, inf, -inf, 0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::max(),
          -std::numeric_limits<float>::max(), std::numeric_limits<float>::min(),
          std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(), 0.5f, 2.0f, 3.0f};
}

// Random floats with the specials spread through them, so each special meets random values
// and every special on every lane position of every width.
inline std::vector<float> floats_with_specials(int count, std::uint32_t seed) {
  std::vector<float> out = random_floats(count, seed, -100.0f, 100.0f);
  const std::vector<float> specials = special_floats();
  std::mt19937 rng(seed * 7 + 1);
  for (int i = 0; i < count; i += 3) out[i] = specials[rng() % specials.size()];
  return out;
}

// Equal bit patterns, or both NaN (NaN payloads are not part of the contract).
inline bool same_float(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) || (std::isnan(a) && std::isnan(b));
}

inline ::testing::AssertionResult floats_match(const std::vector<float>& got, const std::vector<float>& want,
                                                const char* what) {
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (!same_float(got[i], want[i]))
      return ::testing::AssertionFailure() << what << ": lane " << i << " got " << got[i] << " (0x" << std::hex
                                           << std::bit_cast<std::uint32_t>(got[i]) << "), expected " << want[i]
                                           << " (0x" << std::bit_cast<std::uint32_t>(want[i]) << ")";
  }
  return ::testing::AssertionSuccess();
}

template <typename T>
::testing::AssertionResult ints_match(const std::vector<T>& got, const std::vector<T>& want, const char* what) {
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (got[i] != want[i])
      return ::testing::AssertionFailure() << what << ": lane " << i << " got " << got[i] << ", expected " << want[i];
  }
  return ::testing::AssertionSuccess();
}

}  // namespace lancer::test
