// Everything one lancer-bench run measured, kept raw (every repetition) for the reports.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "accel/kd_stats.h"
#include "bench_options.h"
#include "render/ray_sets.h"
#include "simd/isa.h"

namespace lancer::bench {

// One mode's repetitions of one row.
struct ModeTiming {
  Mode mode = Mode::Packet;
  std::string call;             // what was timed, e.g. "intersect_packet (64-ray chunks)"
  int passes = 1;               // passes over the whole set per run (short sets repeat, see bench_runner.h)
  std::vector<double> seconds;  // per run, in run order: its wall time divided by `passes`
};

// Mrays/s of `rays` traced once in each of `seconds`, and their median, min and max.
struct RateSummary {
  double median = 0.0, min = 0.0, max = 0.0;
};
RateSummary summarize(const std::vector<double>& seconds, std::size_t rays);

// One (scene, set, isa, threads): every mode's timings, or why it was not timed.
struct Row {
  RaySet set = RaySet::Primary;
  Isa isa = Isa::Scalar;
  int threads = 1;  // actual thread count
  std::size_t rays = 0;
  std::vector<ModeTiming> modes;  // in the order of the options; empty when failed
  std::string failure;            // non-empty: the row was not timed (or its timing discarded), and why
};

// The checks of one (scene, set, isa) before anything was timed.
struct SetCheck {
  RaySet set = RaySet::Primary;
  Isa isa = Isa::Scalar;
  std::size_t rays = 0;
  std::size_t answered = 0;  // Lancer's hits (closest) or occluded rays (shadow)
  bool packet_checked = false;
  std::size_t packet_mismatches = 0;  // packet answers not bit-identical to single-ray ones
  bool embree_checked = false;
  std::size_t embree_ties = 0;           // other triangle at the same t (shared edges, vertices)
  std::size_t embree_disagreements = 0;  // anything else
  std::string embree_call;               // the call the embree column times
  bool work_counted = false;
  KdWorkPerRay work;  // of the single-ray kernel (measure_kd_work)
  std::vector<std::pair<std::string, double>> embree_calibration;  // candidate call, Mrays/s (1 thread, best of 2)
  std::string failure;
};

// Build figures of one ISA (the leaf blocks, hence memory, depend on it).
struct IsaBuild {
  Isa isa = Isa::Scalar;
  std::vector<std::pair<int, double>> lancer_ms;  // (threads, build ms)
  std::vector<std::pair<int, double>> embree_ms;  // empty without the embree mode
  std::size_t lancer_bytes = 0;
  std::int64_t embree_bytes = -1;  // -1: not measured
};

struct SceneResult {
  std::string name, origin, source;
  std::size_t triangles = 0;
  bool added_light = false;
  double load_ms = 0.0;
  std::vector<IsaBuild> builds;
  std::vector<SetCheck> checks;
  std::vector<Row> rows;
  std::int64_t peak_rss_bytes = 0;  // of the process, after this scene
  std::string failure;              // non-empty: the scene could not be loaded or built
};

struct BenchRun {
  BenchOptions options;
  std::vector<int> threads;  // actual thread counts, in the options' order
  int hardware_threads = 0;
  std::string embree;                                         // embree_description()
  double load_average_start = -1.0, load_average_end = -1.0;  // 1-minute, from /proc/loadavg
  std::vector<SceneResult> scenes;
  double wall_seconds = 0.0;
  std::int64_t peak_rss_bytes = 0;

  bool any_failure() const;
};

}  // namespace lancer::bench
