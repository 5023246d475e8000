// The SIMD-primitive benchmarks' data, per-ISA tables and scalar reference (see
// simd_bench_reference.h). Built with the generic flags (-ffp-contract=off), so every
// reference operation below rounds exactly once, as the vector instructions do.
#include "simd_bench_reference.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "simd/splitmix64.h"

namespace lancer::bench {
namespace {

constexpr int kPasses = 4;
static_assert(kPasses * kSimdLength * 1023.0 < 0x1p24, "reduce_add's float sums stay exact");

std::string mismatch(const char* what, int at, double got, double want) {
  char text[200];
  std::snprintf(text, sizeof text, "%s[%d] is %.9g but the scalar reference gives %.9g", what, at, got, want);
  return text;
}

// Bit-for-bit comparison of out[0 .. count) with want.
std::string compare(const float* out, const std::vector<float>& want) {
  for (std::size_t i = 0; i < want.size(); ++i)
    if (std::bit_cast<std::uint32_t>(out[i]) != std::bit_cast<std::uint32_t>(want[i]))
      return mismatch("out", int(i), out[i], want[i]);
  return {};
}

// Each chain lane's final value: step applied kSimdSteps times to x[i].
template <typename Step>
std::vector<float> chains(const SimdInputs& in, int width, Step step) {
  std::vector<float> want(std::size_t(kSimdChains * width));
  for (std::size_t i = 0; i < want.size(); ++i) {
    float v = in.x[i];
    for (int s = 0; s < kSimdSteps; ++s) v = step(v);
    want[i] = v;
  }
  return want;
}

// rcp is approximate on the vector ISAs. Each step's result is 1/v times (1 + e) with
// |e| <= bound, so after n steps |log(v_n / exact_n)| <= n * -log(1 - bound); exact_n is
// computed in double (its own rounding adds at most n * 2^-53).
std::string check_rcp_chains(const float* out, const SimdInputs& in, int width, float bound) {
  const double limit = kSimdSteps * (-std::log1p(-double(bound))) + kSimdSteps * 0x1p-52;
  for (int i = 0; i < kSimdChains * width; ++i) {
    double exact = in.x[i];
    for (int s = 0; s < kSimdSteps; ++s) exact = 1.0 / exact;
    const double error = std::fabs(std::log(double(out[i]) / exact));
    if (!(error <= limit)) {
      char text[200];
      std::snprintf(text, sizeof text, "out[%d] is %.9g, %.3g (log ratio) from the exact %.9g; the bound is %.3g", i,
                    double(out[i]), error, exact, limit);
      return text;
    }
  }
  return {};
}

float less_or(float a, float b, float t) { return a < t ? a : b; }

}  // namespace

SimdBenchData::SimdBenchData()
    : x(kSimdLength), y(kSimdLength), ints(kSimdLength), out(kSimdLength), index(kSimdLength) {
  SplitMix64 rng(20240605);
  for (int i = 0; i < kSimdLength; ++i) {
    x[i] = 1.0f + rng.uniform();
    y[i] = 1.0f + rng.uniform();
    ints[i] = std::floor(rng.uniform() * 1024.0f);
    index[i] = static_cast<std::int32_t>(rng.uniform() * float(kSimdLength));
  }
  inputs = SimdInputs{x.data(), y.data(), ints.data(), index.data(), kPasses,
                      /*add_c=*/0.1f, /*mul_c=*/1.001f, /*fma_m=*/0.999f, /*fma_c=*/0.002f,
                      /*div_c=*/1.001f, /*sqrt_c=*/1.3f, /*threshold=*/1.5f};
}

std::optional<SimdKernels> simd_kernels_for(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return scalar::simd_bench_kernels();
#if defined(__x86_64__) || defined(_M_X64)
    case Isa::Sse4: return sse4::simd_bench_kernels();
    case Isa::Avx2: return avx2::simd_bench_kernels();
    case Isa::Avx512: return avx512::simd_bench_kernels();
#endif
    default: return std::nullopt;
  }
}

const char* simd_op_name(SimdOp op) {
  constexpr const char* kNames[kSimdOpCount] = {"add",    "mul",          "fma",    "div",        "rcp",        "sqrt",
                                                "minmax", "cmp_movemask", "select", "reduce_add", "load_store", "gather"};
  return kNames[static_cast<int>(op)];
}

std::int64_t simd_items_per_call(SimdOp op, int width, const SimdInputs& in) {
  switch (op) {
    case SimdOp::Add:
    case SimdOp::Mul:
    case SimdOp::Fma:
    case SimdOp::Div:
    case SimdOp::Rcp:
    case SimdOp::Sqrt: return std::int64_t(kSimdChains) * width * kSimdSteps;
    default: return std::int64_t(kSimdLength) * in.passes;
  }
}

std::string check_simd_kernel(SimdOp op, const SimdKernels& kernels, SimdBenchData& data) {
  const SimdInputs& in = data.inputs;
  const int n = kernels.width;
  float* out = data.out.data();
  for (float& o : data.out) o = std::numeric_limits<float>::quiet_NaN();  // nothing stale passes
  const double result = kernels.op[static_cast<int>(op)](in, out);

  switch (op) {
    case SimdOp::Add: return compare(out, chains(in, n, [&](float v) { return v + in.add_c; }));
    case SimdOp::Mul: return compare(out, chains(in, n, [&](float v) { return v * in.mul_c; }));
    case SimdOp::Fma: return compare(out, chains(in, n, [&](float v) { return std::fma(v, in.fma_m, in.fma_c); }));
    case SimdOp::Div: return compare(out, chains(in, n, [&](float v) { return v / in.div_c; }));
    case SimdOp::Rcp: return check_rcp_chains(out, in, n, kernels.rcp_max_rel_error);
    case SimdOp::Sqrt: return compare(out, chains(in, n, [&](float v) { return std::sqrt(v) * in.sqrt_c; }));
    case SimdOp::MinMax: {
      // Pair p folds vectors i with i % pairs == p (its first vector included twice).
      const int pairs = kSimdChains / 2;
      std::vector<float> want(std::size_t(2 * pairs * n));
      for (int i = 0; i < pairs * n; ++i) want[std::size_t(i)] = want[std::size_t(pairs * n + i)] = in.x[i];
      for (int i = 0; i < kSimdLength; ++i) {
        float& lo = want[std::size_t((i / n) % pairs * n + i % n)];
        float& hi = want[std::size_t((pairs + (i / n) % pairs) * n + i % n)];
        lo = in.x[i] < lo ? in.x[i] : lo;
        hi = in.x[i] > hi ? in.x[i] : hi;
      }
      return compare(out, want);
    }
    case SimdOp::CmpMovemask: {
      double want = 0.0;
      for (int i = 0; i < kSimdLength; ++i)
        if (in.x[i] < in.threshold) want += double(1 << (i % n));
      want *= in.passes;
      return result == want ? std::string() : mismatch("result", 0, result, want);
    }
    case SimdOp::Select: {
      std::vector<float> want(kSimdLength);
      for (int i = 0; i < kSimdLength; ++i) want[std::size_t(i)] = less_or(in.x[i], in.y[i], in.threshold);
      return compare(out, want);
    }
    case SimdOp::ReduceAdd: {
      double want = 0.0;
      for (int i = 0; i < kSimdLength; ++i) want += in.ints[i];
      want *= in.passes;
      return result == want ? std::string() : mismatch("result", 0, result, want);
    }
    case SimdOp::LoadStore: return compare(out, std::vector<float>(in.x, in.x + kSimdLength));
    case SimdOp::Gather: {
      // Accumulator k sums the vectors i of index with i % kSimdChains == k, each pass.
      std::vector<float> want(std::size_t(kSimdChains * n), 0.0f);
      for (int p = 0; p < in.passes; ++p)
        for (int i = 0; i < kSimdLength; ++i)
          want[std::size_t((i / n) % kSimdChains * n + i % n)] += in.ints[in.index[i]];
      return compare(out, want);
    }
  }
  return "unknown operation";
}

}  // namespace lancer::bench
