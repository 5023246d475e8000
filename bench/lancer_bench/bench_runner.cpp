#include "bench_runner.h"

#include <sys/resource.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <new>
#include <ostream>
#include <stdexcept>
#include <string>

#include "accel/kd_tree.h"
#include "bench_checks.h"
#include "bench_trace.h"
#include "embree_tracer.h"
#include "simd/out_of_memory.h"

namespace lancer::bench {

namespace {

// The seed of the diffuse and shadow sets (that of `lancer rays`).
constexpr std::uint64_t kRaySeed = 0;

std::int64_t peak_rss_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return -1;
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

double load_average() {
  std::ifstream in("/proc/loadavg");
  double one_minute = -1.0;
  if (!(in >> one_minute)) return -1.0;
  return one_minute;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string describe_hit(const Hit& h) {
  if (!h.valid()) return "miss";
  char buf[96];
  std::snprintf(buf, sizeof buf, "triangle %u at t %.9g", h.prim, static_cast<double>(h.t));
  return buf;
}

// One arena per thread count of the run (task_arena(1) traces on the calling thread only).
struct Arenas {
  std::vector<int> counts;
  std::vector<std::unique_ptr<tbb::task_arena>> arenas;

  explicit Arenas(const std::vector<int>& requested) {
    for (int t : requested) {
      const int n = t > 0 ? t : tbb::info::default_concurrency();
      if (std::find(counts.begin(), counts.end(), n) != counts.end()) continue;
      counts.push_back(n);
      arenas.push_back(std::make_unique<tbb::task_arena>(n));
      arenas.back()->initialize();
    }
  }
  // The arena with the most threads: the one the untimed checks trace on.
  tbb::task_arena& widest() {
    const auto i = std::max_element(counts.begin(), counts.end()) - counts.begin();
    return *arenas[static_cast<std::size_t>(i)];
  }
};

bool wants(const BenchOptions& opt, Mode mode) {
  return std::find(opt.modes.begin(), opt.modes.end(), mode) != opt.modes.end();
}

// The accelerators of one ISA: the trees of the last thread count are kept for tracing.
struct IsaAccels {
  std::unique_ptr<KdTree> kd;
  std::unique_ptr<EmbreeScene> embree;
};

IsaAccels build_accels(const TriangleSoA& tris, Isa isa, Arenas& arenas, bool embree, IsaBuild& record) {
  IsaAccels out;
  record.isa = isa;
  for (std::size_t i = 0; i < arenas.counts.size(); ++i) {
    out.kd.reset();  // one tree at a time
    arenas.arenas[i]->execute([&] { out.kd = std::make_unique<KdTree>(tris, KdBuildOptions{}, isa); });
    record.lancer_ms.emplace_back(arenas.counts[i], out.kd->build_ms());
  }
  record.lancer_bytes = out.kd->memory_bytes();
  if (!embree) return out;
  for (int threads : arenas.counts) {
    out.embree.reset();
    out.embree = std::make_unique<EmbreeScene>(tris, isa, threads);
    record.embree_ms.emplace_back(threads, out.embree->build_ms());
  }
  record.embree_bytes = out.embree->memory_bytes();
  return out;
}

// Embree's candidate calls per set: primary rays of an 8x8 tile are coherent; diffuse and
// shadow rays get whichever call is fastest here.
std::vector<EmbreeCall> embree_candidates(RaySet set) {
  switch (set) {
    case RaySet::Primary: return {EmbreeCall::Intersect16Coherent};
    case RaySet::Diffuse: return {EmbreeCall::Intersect1, EmbreeCall::Intersect16};
    case RaySet::Shadow: return {EmbreeCall::Occluded1, EmbreeCall::Occluded16, EmbreeCall::Occluded16Coherent};
  }
  return {};
}

// Times each candidate twice on one thread (interleaved) and returns the fastest.
EmbreeCall choose_embree_call(const EmbreeScene& embree, RaySet set, std::span<const Ray> rays,
                              tbb::task_arena& one_thread, SetCheck& check) {
  const std::vector<EmbreeCall> candidates = embree_candidates(set);
  if (candidates.size() == 1) return candidates.front();
  std::vector<double> best(candidates.size(), 1e300);
  Answers scratch;
  for (int round = 0; round < 2; ++round)
    for (std::size_t c = 0; c < candidates.size(); ++c)
      best[c] = std::min(best[c], trace_embree(embree, candidates[c], rays, one_thread, scratch));
  std::size_t fastest = 0;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const double mrays = best[c] > 0.0 ? static_cast<double>(rays.size()) / best[c] * 1e-6 : 0.0;
    check.embree_calibration.emplace_back(std::string(embree_call_name(candidates[c])), mrays);
    if (best[c] < best[fastest]) fastest = c;
  }
  return candidates[fastest];
}

// What the timed runs must reproduce, checked before any timing.
struct References {
  Answers lancer, embree;
  EmbreeCall call = EmbreeCall::Intersect1;
  // Seconds of the checking pass of each mode, on the widest arena (`threads` threads).
  std::map<Mode, double> check_seconds;
  int threads = 1;
};

// Passes per run so that a run on `threads` threads lasts about kMinRunSeconds, estimated
// from the checking pass (perfect scaling assumed, so fewer threads never get fewer passes
// than needed).
int passes_per_run(const References& ref, Mode mode, int threads) {
  const auto found = ref.check_seconds.find(mode);
  if (found == ref.check_seconds.end() || !(found->second > 0.0)) return 1;
  const double estimate = found->second * static_cast<double>(ref.threads) / static_cast<double>(threads);
  return static_cast<int>(std::clamp(std::ceil(kMinRunSeconds / estimate), 1.0, 1000.0));
}

SetCheck check_set(RaySet set, Isa isa, std::span<const Ray> rays, const IsaAccels& accels, const BenchOptions& opt,
                   Arenas& arenas, tbb::task_arena& one_thread, References& ref) {
  SetCheck check;
  check.set = set;
  check.isa = isa;
  check.rays = rays.size();
  const bool occlusion = set == RaySet::Shadow;
  tbb::task_arena& arena = arenas.widest();
  ref.threads = arena.max_concurrency();
  ref.check_seconds[Mode::Single] = trace_lancer(*accels.kd, Mode::Single, occlusion, rays, arena, ref.lancer);
  check.answered = occlusion
                       ? static_cast<std::size_t>(std::count(ref.lancer.occluded.begin(), ref.lancer.occluded.end(), 1))
                       : static_cast<std::size_t>(std::count_if(ref.lancer.hits.begin(), ref.lancer.hits.end(),
                                                                [](const Hit& h) { return h.valid(); }));
  arena.execute([&] { check.work = measure_kd_work(*accels.kd, rays, occlusion); });
  check.work_counted = !rays.empty();
  if (wants(opt, Mode::Packet)) {
    Answers packet;
    ref.check_seconds[Mode::Packet] = trace_lancer(*accels.kd, Mode::Packet, occlusion, rays, arena, packet);
    std::size_t first = 0;
    check.packet_checked = true;
    check.packet_mismatches = occlusion ? count_bit_differences(packet.occluded, ref.lancer.occluded, first)
                                        : count_bit_differences(packet.hits, ref.lancer.hits, first);
    if (check.packet_mismatches > 0) {
      check.failure = "packet answers differ from single-ray answers on " + std::to_string(check.packet_mismatches) +
                      " of " + std::to_string(rays.size()) + " rays (first: ray " + std::to_string(first) + ")";
      if (!occlusion)
        check.failure +=
            ": packet " + describe_hit(packet.hits[first]) + ", single " + describe_hit(ref.lancer.hits[first]);
      return check;
    }
  }
  if (accels.embree) {
    ref.call = choose_embree_call(*accels.embree, set, rays, one_thread, check);
    check.embree_call = std::string(embree_call_name(ref.call));
    ref.check_seconds[Mode::Embree] = trace_embree(*accels.embree, ref.call, rays, arena, ref.embree);
    accels.embree->check_errors();
    const Agreement a = occlusion ? compare_occlusion(ref.lancer.occluded, ref.embree.occluded)
                                  : compare_closest(rays, ref.lancer.hits, ref.embree.hits, accels.kd->max_extent_up());
    check.embree_checked = true;
    check.embree_ties = a.ties;
    check.embree_disagreements = a.disagreements;
    if (!a.acceptable()) {
      const std::size_t i = a.first_disagreement;
      check.failure =
          "Lancer and Embree disagree on " + std::to_string(a.disagreements) + " of " + std::to_string(rays.size()) +
          " rays (more than 0.1%; ties at equal t excluded), first: ray " + std::to_string(i) + ": " +
          (occlusion ? std::string("Lancer ") + (ref.lancer.occluded[i] ? "occluded" : "clear") + ", Embree " +
                           (ref.embree.occluded[i] ? "occluded" : "clear")
                     : "Lancer " + describe_hit(ref.lancer.hits[i]) + ", Embree " + describe_hit(ref.embree.hits[i]));
    }
  }
  return check;
}

// Times every mode `reps` times on `arena`, interleaved; the last run of each mode must
// give the reference answers.
Row time_row(RaySet set, Isa isa, int threads, std::span<const Ray> rays, const IsaAccels& accels,
             const BenchOptions& opt, tbb::task_arena& arena, const References& ref) {
  Row row;
  row.set = set;
  row.isa = isa;
  row.threads = threads;
  row.rays = rays.size();
  const bool occlusion = set == RaySet::Shadow;
  std::vector<Answers> answers(opt.modes.size());
  for (Mode m : opt.modes) {
    ModeTiming t;
    t.mode = m;
    t.call = m == Mode::Embree ? std::string(embree_call_name(ref.call)) : lancer_call_name(m, occlusion);
    t.passes = passes_per_run(ref, m, threads);
    row.modes.push_back(t);
  }
  for (int rep = 0; rep < opt.reps; ++rep)
    for (std::size_t i = 0; i < opt.modes.size(); ++i) {
      const Mode m = opt.modes[i];
      double s = 0.0;
      for (int pass = 0; pass < row.modes[i].passes; ++pass)
        s += m == Mode::Embree ? trace_embree(*accels.embree, ref.call, rays, arena, answers[i])
                               : trace_lancer(*accels.kd, m, occlusion, rays, arena, answers[i]);
      row.modes[i].seconds.push_back(s / row.modes[i].passes);
    }
  for (std::size_t i = 0; i < opt.modes.size(); ++i) {
    const Answers& expected = opt.modes[i] == Mode::Embree ? ref.embree : ref.lancer;
    std::size_t first = 0;
    const std::size_t diff = occlusion ? count_bit_differences(answers[i].occluded, expected.occluded, first)
                                       : count_bit_differences(answers[i].hits, expected.hits, first);
    if (diff > 0) {
      row.failure = std::string(mode_name(opt.modes[i])) +
                    ": the timed runs gave other answers than the checked run on " + std::to_string(diff) +
                    " rays (first: ray " + std::to_string(first) + "); timings discarded";
      row.modes.clear();
      break;
    }
  }
  return row;
}

void log_check(std::ostream& log, const std::string& scene, const SetCheck& c) {
  log << "[check] " << scene << " " << ray_set_name(c.set) << " " << isa_name(c.isa) << ": " << c.rays << " rays, "
      << c.answered << (c.set == RaySet::Shadow ? " occluded" : " hits");
  if (c.packet_checked && c.packet_mismatches == 0) log << "; packet == single on every ray";
  if (!c.embree_calibration.empty()) {
    log << "; Embree calls (1 thread):";
    for (const auto& [call, mrays] : c.embree_calibration) log << " " << call << " " << fixed(mrays, 2) << " Mrays/s,";
    log << " using " << c.embree_call;
  }
  if (c.embree_checked)
    log << "; Embree: " << c.embree_ties << " ties at equal t, " << c.embree_disagreements << " other disagreements";
  log << "\n";
  if (!c.failure.empty())
    log << "[FAILED] " << scene << " " << ray_set_name(c.set) << " " << isa_name(c.isa) << ": " << c.failure
        << " -- not timed\n";
}

std::string ms_list(const std::vector<std::pair<int, double>>& ms) {
  std::string s;
  for (const auto& [threads, v] : ms)
    s += (s.empty() ? "" : ", ") + fixed(v, 1) + " ms (" + std::to_string(threads) + "t)";
  return s;
}

void run_scene(const SuiteScene& entry, const BenchOptions& opt, Arenas& arenas, tbb::task_arena& one_thread,
               SceneResult& result, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  const BenchScene bench = load_bench_scene(entry, opt.size);
  result.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  result.source = bench.scene.source;
  result.triangles = bench.scene.triangles.size();
  result.added_light = bench.added_light;
  log << "[scene] " << entry.name << " (" << entry.origin << "): " << result.triangles << " triangles, loaded in "
      << fixed(result.load_ms, 0) << " ms"
      << (bench.added_light ? "; no light: added a point light for shadow rays" : "") << "\n";

  std::map<RaySet, std::vector<Ray>> sets;
  for (Isa isa : opt.isas) {
    IsaBuild build;
    const IsaAccels accels = build_accels(bench.scene.triangles, isa, arenas, wants(opt, Mode::Embree), build);
    log << "[build] " << entry.name << " " << isa_name(isa) << ": Lancer " << ms_list(build.lancer_ms) << ", "
        << build.lancer_bytes << " bytes";
    if (accels.embree)
      log << "; Embree (max_isa " << embree_isa_cap(isa) << ") " << ms_list(build.embree_ms) << ", "
          << build.embree_bytes << " bytes";
    log << "\n";
    result.builds.push_back(build);

    for (RaySet set : opt.sets) {
      std::vector<Ray>& rays = sets[set];
      if (rays.empty()) rays = make_ray_set(bench.scene, *accels.kd, bench.camera, set, kRaySeed);
      References ref;
      SetCheck check;
      if (rays.empty()) {
        check.set = set;
        check.isa = isa;
        check.failure = "no rays: no camera ray hits the scene";
      } else {
        check = check_set(set, isa, rays, accels, opt, arenas, one_thread, ref);
      }
      log_check(log, entry.name, check);
      for (std::size_t t = 0; t < arenas.counts.size(); ++t) {
        Row row;
        if (check.failure.empty()) {
          row = time_row(set, isa, arenas.counts[t], rays, accels, opt, *arenas.arenas[t], ref);
          if (!row.failure.empty())
            log << "[FAILED] " << entry.name << " " << ray_set_name(set) << ": " << row.failure << "\n";
        } else {
          row.set = set;
          row.isa = isa;
          row.threads = arenas.counts[t];
          row.rays = rays.size();
          row.failure = check.failure;
        }
        result.rows.push_back(std::move(row));
      }
      result.checks.push_back(std::move(check));
    }
  }
}

}  // namespace

RateSummary summarize(const std::vector<double>& seconds, std::size_t rays) {
  RateSummary s;
  if (seconds.empty()) return s;
  std::vector<double> rates;
  for (double v : seconds) rates.push_back(v > 0.0 ? static_cast<double>(rays) / v * 1e-6 : 0.0);
  std::sort(rates.begin(), rates.end());
  const std::size_t n = rates.size();
  s.median = n % 2 == 1 ? rates[n / 2] : 0.5 * (rates[n / 2 - 1] + rates[n / 2]);
  s.min = rates.front();
  s.max = rates.back();
  return s;
}

bool BenchRun::any_failure() const {
  for (const SceneResult& s : scenes) {
    if (!s.failure.empty()) return true;
    for (const Row& r : s.rows)
      if (!r.failure.empty()) return true;
  }
  return false;
}

BenchRun run_suite(const BenchOptions& options, const std::vector<SuiteScene>& scenes, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  BenchRun run;
  run.options = options;
  run.hardware_threads = tbb::info::default_concurrency();
  run.embree = embree_description();
  run.load_average_start = load_average();
  Arenas arenas(options.threads);
  run.threads = arenas.counts;
  tbb::task_arena one_thread(1);
  one_thread.initialize();

  for (std::size_t i = 0; i < scenes.size(); ++i) {
    SceneResult result;
    result.name = scenes[i].name;
    result.origin = scenes[i].origin;
    log << "[" << i + 1 << "/" << scenes.size() << "] " << scenes[i].name << "\n";
    try {
      run_scene(scenes[i], options, arenas, one_thread, result, log);
    } catch (const std::bad_alloc& e) {
      result.failure = out_of_memory_message(e);
    } catch (const std::exception& e) {
      result.failure = e.what();
    }
    if (!result.failure.empty()) log << "[FAILED] " << scenes[i].name << ": " << result.failure << "\n";
    result.peak_rss_bytes = peak_rss_bytes();
    run.scenes.push_back(std::move(result));
  }
  run.load_average_end = load_average();
  run.peak_rss_bytes = peak_rss_bytes();
  run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace lancer::bench
