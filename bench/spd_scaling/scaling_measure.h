// One point of lancer-spd-scaling: generate an SPD scene, build Lancer's kd-tree on one
// thread, and trace the SPD view's primary rays (tile order) on one thread, in packet and
// single-ray mode. The packet answers must equal the single-ray ones bit for bit before
// anything is timed; the repetitions alternate between the two modes, so that a busy
// moment of the shared machine hits both alike.
//
// Build and trace times are CPU seconds of the one thread that does the work (checked:
// the one-thread task arena runs every task on the calling thread), so that other
// programs on a shared machine, which take the core away for a while, do not count. They
// still compete for caches and memory bandwidth, which CPU time does not remove.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>

#include "bench_results.h"
#include "scaling_points.h"
#include "simd/isa.h"

namespace lancer::bench {

struct ScalingSettings {
  int image = 512;  // image side in pixels (the SPD renders 512 x 512), a multiple of 8
  int reps = 5;     // timed runs per mode
  Isa isa = best_supported_isa();
  // Builds per point: the median is reported. Large scenes are built once (a build of
  // 10^7 triangles takes tens of seconds, and its noise is relatively small).
  int builds = 3;
  std::uint64_t single_build_above = 1'000'000;
  // The lancer-spd-scaling executable that measures a point's peak memory in a child
  // process (measure_peak_in_child); empty: the peak is not measured.
  std::string peak_program;
};

struct ScalingResult {
  ScalingPoint point;
  double generate_ms = 0.0;
  double build_ms = 0.0;  // CPU ms, median over `build_runs` one-thread builds
  int build_runs = 0;
  std::size_t accel_bytes = 0;  // KdTree::memory_bytes
  // Peak resident memory of generating the scene and building its tree, above the
  // resident memory before, measured in a fresh process (see measure_peak_in_child);
  // -1 when it could not be measured.
  std::int64_t peak_load_build_bytes = -1;
  std::size_t rays = 0, hits = 0;
  RateSummary packet, single;  // primary Mrays per CPU second, one thread
  int passes = 1;              // passes over the rays per timed run
  std::int64_t peak_rss_bytes = 0;  // of the process, after this point
  bool skipped = false;        // not measured because memory would not suffice
  bool over_bound = false;     // measured, but its peak is over kPeakBoundBytesPerTriangle
  std::string failure;         // non-empty: skipped or failed, and why

  double bytes_per_triangle() const {
    return point.triangles ? static_cast<double>(accel_bytes) / static_cast<double>(point.triangles) : 0.0;
  }
  double peak_bytes_per_triangle() const {
    return point.triangles && peak_load_build_bytes >= 0
               ? static_cast<double>(peak_load_build_bytes) / static_cast<double>(point.triangles)
               : 0.0;
  }
};

// What one point needs at its peak (scene, build and tree together), per triangle, for
// skipping points that would not fit: issue 15's bound, kPeakBoundBytesPerTriangle, plus
// room for the traced rays and their answers (512 x 512 of each, tens of MB).
inline constexpr double kPeakBytesPerTriangle = 300.0;

// Issue 15: generating and building stay at or below this many bytes per triangle at
// their peak. A point above it fails (exit status 1), so the series checks the bound.
// It applies from the series' first decade up: on smaller scenes the few hundred KB that
// do not scale with the scene (page granularity, per-thread buffers) are most of it.
inline constexpr double kPeakBoundBytesPerTriangle = 200.0;
inline constexpr std::uint64_t kPeakBoundFromTriangles = 10'000;

// The peak of generation + build of `point`, measured in a fresh process running
// `program` (lancer-spd-scaling) with kPeakChildOption: a process that has run other
// points holds freed memory that the next one reuses without it showing as resident
// growth. The child builds with all threads, as `lancer` does. Returns -1 and sets
// `error` when it fails.
std::int64_t measure_peak_in_child(const std::string& program, const ScalingPoint& point, Isa isa,
                                   std::string& error);

// This process's executable (/proc/self/exe), or "" when it cannot be read.
std::string this_executable();

// The child's side: `lancer-spd-scaling --peak-of SPD SIZE` generates, builds, and prints
// "peak_bytes N" on stdout (VmHWM after, less VmRSS before). Exit status 0 or 1.
inline constexpr const char* kPeakChildOption = "--peak-of";
int run_peak_child(const std::string& spd, int size, Isa isa);

// MemAvailable of /proc/meminfo in bytes, or -1 when it cannot be read.
std::int64_t available_memory_bytes();

// Measures `point`. Never throws for the point's own failures (out of memory, a check
// that fails): they are recorded in `failure` and logged. A point whose estimated peak
// (kPeakBytesPerTriangle) exceeds `memory_limit` bytes is skipped (no limit when < 0).
ScalingResult measure_scaling_point(const ScalingPoint& point, const ScalingSettings& settings,
                                    std::int64_t memory_limit, std::ostream& log);

}  // namespace lancer::bench
