// BM_Simd/<isa>/<op>: throughput of the SIMD layer's primitives at each ISA's width
// (scalar 1, sse4 4, avx2 8, avx512 16), in floats per second (items_per_second). What each
// kernel does and what one item is: simd_bench-inl.h. Registered at start-up for the ISAs
// this CPU supports only, so no kernel runs on a CPU without its instructions. Before
// timing, each benchmark runs its kernel once and compares the result with the scalar
// reference (simd_bench_reference.cpp); a mismatch fails the benchmark with the reason.
#include <benchmark/benchmark.h>

#include <string>

#include "simd/isa.h"
#include "simd_bench_reference.h"

namespace {

using namespace lancer;
using namespace lancer::bench;

void bm_simd(benchmark::State& state, SimdKernels kernels, SimdOp op) {
  SimdBenchData data;
  const std::string error = check_simd_kernel(op, kernels, data);
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  const SimdKernel kernel = kernels.op[static_cast<int>(op)];
  const SimdInputs& in = data.inputs;
  float* out = data.out.data();
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernel(in, out));
    benchmark::ClobberMemory();  // out was written
  }
  state.SetItemsProcessed(state.iterations() * simd_items_per_call(op, kernels.width, in));
}

struct Registration {
  Registration() {
    for (Isa isa : supported_isas()) {
      const std::optional<SimdKernels> kernels = simd_kernels_for(isa);
      if (!kernels) continue;
      for (int i = 0; i < kSimdOpCount; ++i) {
        const SimdOp op = static_cast<SimdOp>(i);
        if (kernels->op[i] == nullptr) continue;  // e.g. fma without an FMA instruction
        const std::string name = "BM_Simd/" + std::string(isa_name(isa)) + "/" + simd_op_name(op);
        benchmark::RegisterBenchmark(name.c_str(), bm_simd, *kernels, op);
      }
    }
  }
} registration;

}  // namespace
