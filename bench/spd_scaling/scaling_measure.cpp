#include "scaling_measure.h"

#include <sys/resource.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <new>
#include <ostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "accel/kd_tree.h"
#include "bench_checks.h"
#include "bench_runner.h"
#include "bench_suite.h"
#include "bench_trace.h"
#include "render/ray_sets.h"
#include "simd/out_of_memory.h"
#include "simd/process_memory.h"
#include "simd/release_free_memory.h"

namespace lancer::bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// CPU seconds of the calling thread. On a shared machine a thread's wall time counts the
// time other programs held its core; its CPU time does not.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The CPU seconds of f() on this thread: all of its work, when `one_thread` runs tasks on
// the calling thread only (checked by check_single_threaded).
template <class F>
double cpu_seconds_of(const F& f) {
  const double start = thread_cpu_seconds();
  f();
  return thread_cpu_seconds() - start;
}

// Throws unless `arena` runs every task of a parallel loop on the calling thread, which
// the CPU-time figures rely on.
void check_single_threaded(tbb::task_arena& arena) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> elsewhere{false};
  arena.execute([&] {
    tbb::parallel_for(0, 256, [&](int) {
      if (std::this_thread::get_id() != caller) elsewhere = true;
    });
  });
  if (elsewhere) throw std::runtime_error("the one-thread arena ran tasks on another thread: CPU times would be wrong");
}

std::int64_t peak_rss() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return -1;
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

std::string gib(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return buf;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void measure(const ScalingPoint& point, const ScalingSettings& settings, ScalingResult& r) {
  tbb::task_arena one_thread(1);
  one_thread.initialize();
  check_single_threaded(one_thread);

  auto start = Clock::now();
  auto bench = std::make_unique<BenchScene>(load_bench_scene(spd_entry(point.spd, point.size), settings.image));
  r.generate_ms = ms_since(start);
  if (bench->scene.triangle_count() != point.triangles)
    throw std::runtime_error("generated " + std::to_string(bench->scene.triangle_count()) +
                             " triangles, spd_triangle_count says " + std::to_string(point.triangles));

  const int builds = point.triangles > settings.single_build_above ? 1 : std::max(1, settings.builds);
  std::unique_ptr<KdTree> kd;
  std::vector<double> build_ms;
  for (int b = 0; b < builds; ++b) {
    kd.reset();  // one tree at a time
    const auto build = [&] { kd = std::make_unique<KdTree>(bench->scene.triangles, KdBuildOptions{}, settings.isa); };
    build_ms.push_back(1e3 * cpu_seconds_of([&] { one_thread.execute(build); }));
  }
  r.build_ms = median(build_ms);
  r.build_runs = builds;
  r.accel_bytes = kd->memory_bytes();
  const std::vector<Ray> rays = primary_rays(bench->camera);
  bench.reset();  // the tree holds its own copy of the triangles
  r.rays = rays.size();

  // The check, and the number of passes per timed run (at least kMinRunSeconds each).
  Answers single, packet;
  const auto trace = [&](Mode mode, Answers& out) {
    return cpu_seconds_of([&] { trace_lancer(*kd, mode, false, rays, one_thread, out); });
  };
  const double single_s = trace(Mode::Single, single);
  const double packet_s = trace(Mode::Packet, packet);
  std::size_t first = 0;
  const std::size_t differ = count_bit_differences(packet.hits, single.hits, first);
  if (differ > 0)
    throw std::runtime_error("packet answers differ from single-ray answers on " + std::to_string(differ) + " of " +
                             std::to_string(rays.size()) + " rays (first: ray " + std::to_string(first) + ")");
  r.hits = static_cast<std::size_t>(
      std::count_if(single.hits.begin(), single.hits.end(), [](const Hit& h) { return h.valid(); }));
  const double fastest = std::max(1e-9, std::min(single_s, packet_s));
  r.passes = static_cast<int>(std::clamp(std::ceil(kMinRunSeconds / fastest), 1.0, 1000.0));

  std::vector<double> packet_runs, single_runs;
  for (int rep = 0; rep < settings.reps; ++rep)
    for (Mode mode : {Mode::Packet, Mode::Single}) {
      Answers& out = mode == Mode::Packet ? packet : single;
      double s = 0.0;
      for (int pass = 0; pass < r.passes; ++pass) s += trace(mode, out);
      (mode == Mode::Packet ? packet_runs : single_runs).push_back(s / r.passes);
    }
  if (count_bit_differences(packet.hits, single.hits, first) > 0)
    throw std::runtime_error("the timed runs gave other answers than the checked run");
  r.packet = summarize(packet_runs, rays.size());
  r.single = summarize(single_runs, rays.size());
}

}  // namespace

int run_peak_child(const std::string& spd, int size, Isa isa) {
  try {
    // The baseline is a process that has built a tree before: oneTBB's worker threads
    // and their stacks, malloc's per-thread arenas and first pages, a few MB whatever the
    // scene, are not the scene's cost. The 4,096-triangle tetra is built on the parallel
    // path (not the lean one its size would get), so that those threads exist.
    {
      const BenchScene warm_up = load_bench_scene(spd_entry("tetra", 6), 8);
      KdBuildOptions parallel;
      parallel.one_thread_below = 0;
      const KdTree kd(warm_up.scene.triangles, parallel);
      (void)kd;
    }
    release_free_memory();  // what the warm-up freed must not serve the point unseen
    const std::int64_t before = resident_bytes();
    {
      const BenchScene bench = load_bench_scene(spd_entry(spd, size), 8);
      const KdTree kd(bench.scene.triangles, KdBuildOptions{}, isa);
      (void)kd;
    }
    const std::int64_t peak = peak_resident_bytes();
    if (before < 0 || peak < 0) throw std::runtime_error("cannot read /proc/self/status");
    std::printf("peak_bytes %lld\n", static_cast<long long>(peak - before));
    return 0;
  } catch (const std::bad_alloc& e) {
    std::fprintf(stderr, "%s\n", out_of_memory_message(e).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
  }
  return 1;
}

std::string this_executable() {
  char self[4096];
  const ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
  if (len <= 0) return "";
  self[len] = '\0';
  return self;
}

std::int64_t measure_peak_in_child(const std::string& program, const ScalingPoint& point, Isa isa,
                                   std::string& error) {
  if (program.empty() || program.find('\'') != std::string::npos) {
    error = "no program to measure the peak with: '" + program + "'";
    return -1;
  }
  const std::string command = "'" + program + "' " + kPeakChildOption + " " + point.spd + " " +
                              std::to_string(point.size) + " " + std::string(isa_name(isa)) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    error = "cannot start the peak measurement";
    return -1;
  }
  std::string output;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe)) output += buf;
  const int status = pclose(pipe);
  long long bytes = -1;
  if (status != 0 || std::sscanf(output.c_str(), "peak_bytes %lld", &bytes) != 1 || bytes < 0) {
    error = "peak measurement failed: " + (output.empty() ? std::string("no output") : output);
    while (!error.empty() && error.back() == '\n') error.pop_back();
    return -1;
  }
  return bytes;
}

std::int64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::int64_t kib = 0;
  while (in >> key >> kib) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return kib * 1024;
  }
  return -1;
}

ScalingResult measure_scaling_point(const ScalingPoint& point, const ScalingSettings& settings,
                                    std::int64_t memory_limit, std::ostream& log) {
  ScalingResult r;
  r.point = point;
  const double need = kPeakBytesPerTriangle * static_cast<double>(point.triangles);
  if (memory_limit >= 0 && need > static_cast<double>(memory_limit)) {
    r.skipped = true;
    r.failure = "skipped: needs about " + gib(need) + ", " + gib(static_cast<double>(memory_limit)) + " available";
    log << "[skip] " << point.name() << ": " << r.failure << "\n";
    return r;
  }
  log << "[point] " << point.name() << ": " << point.triangles << " triangles\n" << std::flush;
  try {
    if (!settings.peak_program.empty()) {
      std::string peak_error;
      r.peak_load_build_bytes = measure_peak_in_child(settings.peak_program, point, settings.isa, peak_error);
      if (r.peak_load_build_bytes < 0) throw std::runtime_error(peak_error);
    }
    measure(point, settings, r);
  } catch (const std::bad_alloc& e) {
    r.failure = out_of_memory_message(e);
  } catch (const std::exception& e) {
    r.failure = e.what();
  }
  r.peak_rss_bytes = peak_rss();
  if (!r.failure.empty()) {
    log << "[FAILED] " << point.name() << ": " << r.failure << "\n";
    return r;
  }
  char line[320];
  std::snprintf(line, sizeof line,
                "[done] %s: generated in %.0f ms, built in %.0f CPU ms (1 thread, median of %d), %.1f bytes/triangle, "
                "peak of generation + build %.1f bytes/triangle, packet %.2f single %.2f Mrays per CPU second, "
                "process peak RSS so far %s\n",
                point.name().c_str(), r.generate_ms, r.build_ms, r.build_runs, r.bytes_per_triangle(),
                r.peak_bytes_per_triangle(), r.packet.median, r.single.median,
                gib(static_cast<double>(r.peak_rss_bytes)).c_str());
  log << line << std::flush;
  if (point.triangles >= kPeakBoundFromTriangles && r.peak_bytes_per_triangle() > kPeakBoundBytesPerTriangle) {
    std::snprintf(line, sizeof line, "peak of generation + build %.1f bytes per triangle, over the bound of %.0f",
                  r.peak_bytes_per_triangle(), kPeakBoundBytesPerTriangle);
    r.failure = line;
    r.over_bound = true;
    log << "[FAILED] " << point.name() << ": " << r.failure << "\n";
  }
  return r;
}

}  // namespace lancer::bench
