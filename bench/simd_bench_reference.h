// The generic side of the SIMD-primitive benchmarks: the fixed input data, the kernel
// table of each ISA, and the check of a kernel against the scalar reference (plain float
// arithmetic in generic code, the same operations in the same order per lane).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "simd/aligned_vector.h"
#include "simd_bench_kernels.h"

namespace lancer::bench {

// Buffers and constants for every kernel, from a fixed seed (the same on every machine).
struct SimdBenchData {
  AlignedVector<float> x, y, ints, out;
  AlignedVector<std::int32_t> index;
  SimdInputs inputs{};  // points into the buffers above: do not copy or move the data

  SimdBenchData();
  SimdBenchData(const SimdBenchData&) = delete;
  SimdBenchData& operator=(const SimdBenchData&) = delete;
};

// The table of an ISA this build has kernels for (nullopt: none here, e.g. AVX2 on a
// non-x86 machine). Does not check the CPU: call it only for cpu_supports(isa).
std::optional<SimdKernels> simd_kernels_for(Isa isa);

// "add", "cmp_movemask", ...: the last part of the benchmark name.
const char* simd_op_name(SimdOp op);

// Floats one call of the kernel processes (the unit of items/s).
std::int64_t simd_items_per_call(SimdOp op, int width, const SimdInputs& in);

// Runs the kernel once on `data` and compares what it wrote and returned with the scalar
// reference: bit for bit, except rcp, whose chain must stay within the ISA's documented
// error bound. Returns an empty string when they agree, else what differs.
std::string check_simd_kernel(SimdOp op, const SimdKernels& kernels, SimdBenchData& data);

}  // namespace lancer::bench
