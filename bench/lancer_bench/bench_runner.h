// Runs lancer-bench's measurements. Per scene: load it, build Lancer's kd-tree (and
// Embree's BVH) for every ISA and thread count, make the ray sets; per set and ISA: check
// the answers (packet against single bit for bit, Lancer against Embree up to ties), then
// time every mode, the repetitions interleaved across modes so that a busy moment of a
// shared machine hits all of them alike. A run lasts at least kMinRunSeconds: a set that
// traces faster is traced several times per run (the same number of passes in every run
// of that mode and row), so that timer resolution and scheduler hiccups stay small.
#pragma once

#include <iosfwd>
#include <vector>

#include "bench_options.h"
#include "bench_results.h"
#include "bench_suite.h"

namespace lancer::bench {

inline constexpr double kMinRunSeconds = 0.05;

// Measures `scenes` as `options` say. Progress, checks and failures go to `log` as they
// happen; a scene or set that fails is recorded (and reported) and the run goes on.
BenchRun run_suite(const BenchOptions& options, const std::vector<SuiteScene>& scenes, std::ostream& log);

}  // namespace lancer::bench
