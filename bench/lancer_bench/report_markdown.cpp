#include "report_markdown.h"

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>

#include "bench_runner.h"

namespace lancer::bench {

namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string mib(std::int64_t bytes) { return bytes < 0 ? "n/a" : fixed(static_cast<double>(bytes) / 1048576.0, 0); }

bool has_mode(const BenchRun& run, Mode m) {
  return std::find(run.options.modes.begin(), run.options.modes.end(), m) != run.options.modes.end();
}

const ModeTiming* find_mode(const Row& row, Mode m) {
  for (const ModeTiming& t : row.modes)
    if (t.mode == m) return &t;
  return nullptr;
}

// The build time with `threads`, if measured.
const double* ms_at(const std::vector<std::pair<int, double>>& list, int threads) {
  for (const auto& p : list)
    if (p.first == threads) return &p.second;
  return nullptr;
}

std::string ms_cell(const std::vector<std::pair<int, double>>& list) {
  if (list.empty()) return "n/a";
  std::string s;
  for (const auto& p : list) s += (s.empty() ? "" : " / ") + fixed(p.second, 1);
  return s;
}

std::string threads_header(const BenchRun& run) {
  std::string s;
  for (int t : run.threads) s += (s.empty() ? "" : " / ") + std::to_string(t) + "t";
  return s;
}

void write_setup(const BenchRun& run, std::ostream& out) {
  const BenchOptions& o = run.options;
  std::string isas, sets, modes, threads;
  for (Isa i : o.isas) isas += (isas.empty() ? "" : ", ") + std::string(isa_name(i));
  for (RaySet s : o.sets) sets += (sets.empty() ? "" : ", ") + std::string(ray_set_name(s));
  for (Mode m : o.modes) modes += (modes.empty() ? "" : ", ") + std::string(mode_name(m));
  for (int t : run.threads) threads += (threads.empty() ? "" : ", ") + std::to_string(t);
  out << "# lancer-bench\n\n";
  out << "- Machine: " << run.hardware_threads << " hardware threads; load average (1 min) "
      << fixed(run.load_average_start, 2) << " at the start, " << fixed(run.load_average_end, 2)
      << " at the end (a load above the thread count means shared cores: expect noise)\n";
  out << "- Lancer ISA: " << isas << "; " << run.embree
      << (has_mode(run, Mode::Embree) ? ", ISA capped at Lancer's (max_isa; scalar: sse2)" : " (embree mode not run)")
      << "\n";
  out << "- Image " << o.size << "x" << o.size << " (8x8 tiles); sets: " << sets << "; modes: " << modes
      << "; threads: " << threads << "; " << o.reps << " timed runs per figure\n";
  out << "- Wall time " << fixed(run.wall_seconds, 1) << " s; peak RSS " << mib(run.peak_rss_bytes) << " MiB\n\n";
}

void write_scenes(const BenchRun& run, std::ostream& out) {
  const bool embree = has_mode(run, Mode::Embree);
  const int widest = run.threads.empty() ? 1 : *std::max_element(run.threads.begin(), run.threads.end());
  out << "## Scenes\n\n";
  out << "Build: Lancer SAH kd-tree (KdTree constructor) and Embree high-quality BVH (rtcCommitScene), ms with "
      << threads_header(run) << ". Memory: KdTree::memory_bytes(), and what Embree allocated during the build "
      << "and still holds (memory monitor callback), per triangle. Ratios are Lancer / Embree (" << widest
      << " threads for build). Peak RSS: of the process after the scene.\n\n";
  out << "| scene | origin | triangles | isa | Lancer build ms (" << threads_header(run) << ") | Embree build ms ("
      << threads_header(run) << ") | build L/E | Lancer B/tri | Embree B/tri | memory L/E | peak RSS MiB |\n";
  out << "|---|---|--:|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const SceneResult& s : run.scenes) {
    if (!s.failure.empty()) {
      out << "| " << s.name << " | " << s.origin << " | " << s.triangles << " | | FAILED: " << s.failure
          << " | | | | | | " << mib(s.peak_rss_bytes) << " |\n";
      continue;
    }
    for (const IsaBuild& b : s.builds) {
      const double tris = static_cast<double>(std::max<std::size_t>(1, s.triangles));
      const double* lw = ms_at(b.lancer_ms, widest);
      const double* ew = ms_at(b.embree_ms, widest);
      const std::string build_ratio = lw && ew && *ew > 0.0 ? fixed(*lw / *ew, 2) : "n/a";
      const std::string lbt = fixed(static_cast<double>(b.lancer_bytes) / tris, 1);
      const std::string ebt = b.embree_bytes >= 0 ? fixed(static_cast<double>(b.embree_bytes) / tris, 1) : "n/a";
      const std::string mem_ratio =
          b.embree_bytes > 0 ? fixed(static_cast<double>(b.lancer_bytes) / static_cast<double>(b.embree_bytes), 2)
                             : "n/a";
      out << "| " << s.name << (s.added_light ? " (added light)" : "") << " | " << s.origin << " | " << s.triangles
          << " | " << isa_name(b.isa) << " | " << ms_cell(b.lancer_ms) << " | "
          << (embree ? ms_cell(b.embree_ms) : "n/a") << " | " << build_ratio << " | " << lbt << " | " << ebt << " | "
          << mem_ratio << " | " << mib(s.peak_rss_bytes) << " |\n";
    }
  }
  out << "\n";
}

const SetCheck* find_check(const SceneResult& s, const Row& r) {
  for (const SetCheck& c : s.checks)
    if (c.set == r.set && c.isa == r.isa) return &c;
  return nullptr;
}

std::string work_cell(const SetCheck* c) {
  if (c == nullptr || !c->work_counted) return "n/a";
  return fixed(c->work.inner_steps, 1) + " / " + fixed(c->work.leaves, 1) + " / " + fixed(c->work.triangle_tests, 1);
}

void write_checks(const BenchRun& run, std::ostream& out) {
  out << "## Checks (before timing)\n\n";
  out << "Packet answers against single-ray answers, bit for bit; Lancer's single-ray answers against Embree's: the "
         "same triangle at the same t (relative 1e-4), a tie (another triangle at the same t), or a disagreement. "
         "More than 0.1% disagreements, or any packet mismatch, and the set is not timed.\n\n";
  out << "| scene | set | isa | rays | hits / occluded | packet mismatches | Embree ties | Embree disagreements | "
         "Embree call (calibration, 1 thread) |\n";
  out << "|---|---|---|--:|--:|--:|--:|--:|---|\n";
  for (const SceneResult& s : run.scenes)
    for (const SetCheck& c : s.checks) {
      std::string calib;
      for (const auto& [call, mrays] : c.embree_calibration)
        calib += (calib.empty() ? "" : ", ") + call + " " + fixed(mrays, 2);
      out << "| " << s.name << " | " << ray_set_name(c.set) << " | " << isa_name(c.isa) << " | " << c.rays << " | "
          << c.answered << " | " << (c.packet_checked ? std::to_string(c.packet_mismatches) : "n/a") << " | "
          << (c.embree_checked ? std::to_string(c.embree_ties) : "n/a") << " | "
          << (c.embree_checked ? std::to_string(c.embree_disagreements) : "n/a") << " | "
          << (c.embree_call.empty() ? "n/a" : c.embree_call) << (calib.empty() ? "" : " (" + calib + ")") << " |\n";
    }
  out << "\n";
}

void write_throughput(const BenchRun& run, std::ostream& out) {
  const std::vector<Mode>& modes = run.options.modes;
  const bool embree = has_mode(run, Mode::Embree);
  out << "## Throughput\n\n";
  out << "Mrays/s: median [min-max] of " << run.options.reps
      << " timed runs. A run traces every ray of the set, in 64-ray chunks (one 8x8 tile of the primary set) spread "
         "over the threads, and lasts at least "
      << fixed(kMinRunSeconds * 1000.0, 0)
      << " ms: faster sets are traced several times per run (passes_per_run in the JSON).\n\n";
  out << "| scene | set | rays | isa | threads |";
  for (Mode m : modes) out << " " << mode_name(m) << " |";
  if (embree) out << " embree call |";
  if (embree)
    for (Mode m : modes)
      if (m != Mode::Embree) out << " " << mode_name(m) << " / embree |";
  out << " single-ray work per ray: steps / leaves / tests |";
  out << "\n|---|---|--:|---|--:|";
  for (std::size_t i = 0; i < modes.size(); ++i) out << "--:|";
  if (embree) out << "---|";
  if (embree)
    for (Mode m : modes)
      if (m != Mode::Embree) out << "--:|";
  out << "--:|\n";
  for (const SceneResult& s : run.scenes)
    for (const Row& r : s.rows) {
      out << "| " << s.name << " | " << ray_set_name(r.set) << " | " << r.rays << " | " << isa_name(r.isa) << " | "
          << r.threads << " |";
      if (!r.failure.empty()) {
        for (std::size_t i = 0; i < modes.size(); ++i) out << " failed |";
        if (embree) out << " |";
        if (embree)
          for (Mode m : modes)
            if (m != Mode::Embree) out << " |";
        out << " |\n";
        continue;
      }
      const ModeTiming* e = find_mode(r, Mode::Embree);
      const RateSummary es = e ? summarize(e->seconds, r.rays) : RateSummary{};
      for (Mode m : modes) {
        const RateSummary rs = summarize(find_mode(r, m)->seconds, r.rays);
        out << " " << fixed(rs.median, 2) << " [" << fixed(rs.min, 2) << "-" << fixed(rs.max, 2) << "] |";
      }
      if (embree) out << " " << e->call << " |";
      if (embree)
        for (Mode m : modes)
          if (m != Mode::Embree) {
            const RateSummary rs = summarize(find_mode(r, m)->seconds, r.rays);
            out << " " << (es.median > 0.0 ? fixed(rs.median / es.median, 2) : "n/a") << " |";
          }
      out << " " << work_cell(find_check(s, r)) << " |\n";
    }
  out << "\n";
  out << "Work per ray: of Lancer's single-ray kernel (intersect, or occluded for shadow rays), counted in one extra "
         "pass: inner kd-tree nodes stepped through, leaves entered, triangles tested (a SIMD leaf test counts the "
         "triangles in its lanes, not its width).\n";
  if (embree)
    out << "Embree: primary rays with rtcIntersect16 and RTC_INTERSECT_CONTEXT_FLAG_COHERENT, four 16-ray calls per "
           "8x8 tile; diffuse and shadow rays with whichever candidate call was fastest on one thread for that scene "
           "(checks table). Rays are converted to and from Embree's layout inside the timed calls.\n";
  out << "\n";
}

void write_failures(const BenchRun& run, std::ostream& out) {
  bool any = false;
  for (const SceneResult& s : run.scenes) {
    if (!s.failure.empty()) {
      if (!any) out << "## Failures\n\n";
      any = true;
      out << "- " << s.name << ": " << s.failure << "\n";
    }
    for (const Row& r : s.rows)
      if (!r.failure.empty()) {
        if (!any) out << "## Failures\n\n";
        any = true;
        out << "- " << s.name << " " << ray_set_name(r.set) << " " << isa_name(r.isa) << " " << r.threads
            << " threads: " << r.failure << "\n";
      }
  }
  if (any) out << "\n";
}

}  // namespace

void write_markdown(const BenchRun& run, std::ostream& out) {
  write_setup(run, out);
  write_scenes(run, out);
  write_checks(run, out);
  write_throughput(run, out);
  write_failures(run, out);
}

}  // namespace lancer::bench
