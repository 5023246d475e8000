// lancer-bench's stdout: the run as markdown (setup, scenes, checks, throughput).
#pragma once

#include <iosfwd>

#include "bench_results.h"

namespace lancer::bench {

// Throughput rows: one per scene, set, ISA and thread count, a column per mode
// ("median [min-max]" Mrays/s) and the Lancer / Embree ratios of the medians.
void write_markdown(const BenchRun& run, std::ostream& out);

}  // namespace lancer::bench
