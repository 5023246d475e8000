#include "render_bench.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "accel/accel_factory.h"
#include "bench_suite.h"
#include "cycles_runner.h"
#include "ray_recorder.h"
#include "render/image_io.h"
#include "render/renderer.h"

namespace lancer::bench {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Calls recorded for the traversal share at most (about 40 bytes each).
constexpr std::size_t kMaxRecordedCalls = std::size_t{1} << 26;
// Seeds: the timed renders, and a Lancer reference (independent of the timed samples).
constexpr std::uint64_t kSeed = 0;
constexpr std::uint64_t kReferenceSeed = 0x5EED5EEDull;

double process_cpu_seconds() {
  timespec ts{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Mean over pixels and channels of the squared difference.
double mean_squared_error(const ImageRGB& a, const ImageRGB& ref) {
  if (a.width != ref.width || a.height != ref.height)
    throw std::runtime_error("images of different sizes: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                             " and " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double d = static_cast<double>(a.rgb[i]) - static_cast<double>(ref.rgb[i]);
    sum += d * d;
  }
  return a.rgb.empty() ? 0.0 : sum / static_cast<double>(a.rgb.size());
}

double image_mean(const ImageRGB& a) {
  double sum = 0.0;
  for (float v : a.rgb) sum += v;
  return a.rgb.empty() ? 0.0 : sum / static_cast<double>(a.rgb.size());
}

// The suite's names resolved to files: the project's scenes, the SPD databases and the
// shared meshes through the lancer-bench suite; still-life and the depth-of-field box by path.
SuiteScene resolve(const std::string& name, const fs::path& scenes_dir, const fs::path& models_dir) {
  auto file_scene = [&](const fs::path& file) {
    SuiteScene s;
    s.name = name;
    s.origin = "built-in";
    s.file = file;
    return s;
  };
  if (name == "still-life") return file_scene(scenes_dir / "textured" / "still-life.gltf");
  if (name == "cornell-box-dof") return file_scene(scenes_dir / "cornell-box-dof.gltf");
  return select_scenes(default_suite(scenes_dir, models_dir), {name}).front();
}

bool is_gltf(const fs::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

struct SceneResult {
  std::string name, failure;
  std::size_t triangles = 0;
  double build_s = 0.0, wall_s = 0.0, cpu_s = 0.0, mrays_per_s = 0.0, paths_per_s = 0.0;
  double rays_per_path = 0.0;
  PathBatchStats batches;  // the path tracer's batch counts (of the last timed render)
  double traversal_share = 0.0;  // replayed traversal seconds / render CPU seconds
  ReplayTime replay;
  bool replay_truncated = false;
  bool cycles = false;
  std::string cycles_failure;
  double cycles_s = 0.0, mse_lancer = 0.0, mse_cycles = 0.0, mean_lancer = 0.0, mean_cycles = 0.0, mean_ref = 0.0;
  double equal_error_ratio() const {  // (MSE x seconds) of Cycles over Lancer's
    return mse_lancer > 0.0 && cycles_s > 0.0 ? (mse_cycles * cycles_s) / (mse_lancer * (wall_s + build_s)) : 0.0;
  }
};

RenderSettings settings_for(const RenderBenchOptions& o, int spp, std::uint64_t seed) {
  RenderSettings s;
  s.width = s.height = o.size;
  s.spp = spp;
  s.integrator = IntegratorKind::Path;
  s.max_depth = o.max_depth;
  s.threads = o.threads;
  s.seed = seed;
  s.filter = PixelFilterType::Box;
  s.mode = TraceMode::Packet;
  s.light_samples = o.light_samples;
  return s;
}

fs::path reference_file(const RenderBenchOptions& o, const SuiteScene& entry) {
  const std::string from = o.reference == ReferenceFrom::Cycles ? "cycles" : "lancer";
  return o.cache / (entry.name + "-" + std::to_string(o.size) + "px-depth" + std::to_string(o.max_depth) + "-" + from +
                    "-" + std::to_string(o.reference_spp) + "spp.exr");
}

// The reference image, made once and kept in the cache folder.
ImageRGB reference_image(const RenderBenchOptions& o, const SuiteScene& entry, const BenchScene& bench,
                         const Accelerator& accel, const fs::path& script, std::ostream& err) {
  const fs::path file = reference_file(o, entry);
  if (fs::exists(file)) return read_image(file);
  fs::create_directories(o.cache);
  err << "lancer bench --render: " << entry.name << ": rendering the reference ("
      << (o.reference == ReferenceFrom::Cycles ? "Cycles" : "Lancer") << ", " << o.reference_spp << " spp) to "
      << file.string() << "\n";
  if (o.reference == ReferenceFrom::Cycles) {
    run_cycles(o.blender, script, {entry.file, file, o.size, o.reference_spp, o.max_depth, o.threads, 1});
    return read_image(file);
  }
  RenderStats stats;
  ImageRGB image = render_image(bench.scene, accel, bench.camera, settings_for(o, o.reference_spp, kReferenceSeed), stats);
  write_image(image, file);
  return image;
}

SceneResult measure(const RenderBenchOptions& o, const SuiteScene& entry, bool with_cycles, const fs::path& script,
                    std::ostream& err) {
  SceneResult r;
  r.name = entry.name;
  const BenchScene bench = load_bench_scene(entry, o.size);
  r.triangles = bench.scene.triangle_count();
  const auto t_build = Clock::now();
  const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", bench.scene.triangles, bench.scene.instancing);
  r.build_s = std::chrono::duration<double>(Clock::now() - t_build).count();

  // Timed renders, uninstrumented.
  const RenderSettings timed = settings_for(o, o.spp, kSeed);
  std::vector<double> walls, cpus;
  ImageRGB image;
  RenderStats stats;
  for (int rep = 0; rep < o.reps; ++rep) {
    const double cpu0 = process_cpu_seconds();
    const auto t0 = Clock::now();
    image = render_image(bench.scene, *accel, bench.camera, timed, stats);
    walls.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    cpus.push_back(process_cpu_seconds() - cpu0);
    err << "lancer bench --render: " << entry.name << ": render " << rep + 1 << "/" << o.reps << " "
        << std::fixed << std::setprecision(2) << walls.back() << " s\n";
  }
  r.wall_s = median(walls);
  r.cpu_s = median(cpus);
  const double paths = static_cast<double>(o.size) * o.size * o.spp;
  r.paths_per_s = paths / r.wall_s;
  r.mrays_per_s = static_cast<double>(stats.rays) / r.wall_s * 1e-6;
  r.rays_per_path = static_cast<double>(stats.rays) / paths;
  r.batches = stats.path_batches;

  // The traversal share: the tracer calls of trace_passes passes, replayed alone.
  {
    const RecordingAccelerator recorder(*accel, kMaxRecordedCalls);
    const int passes = std::min(o.trace_passes, o.spp);
    RenderStats rec_stats;
    render_image(bench.scene, recorder, bench.camera, settings_for(o, passes, kSeed), rec_stats);
    r.replay_truncated = recorder.truncated();
    r.replay = replay(*accel, recorder.calls(), 3);
    const double cpu_for_passes = r.cpu_s * passes / o.spp;
    r.traversal_share = cpu_for_passes > 0.0 ? r.replay.total_s() / cpu_for_passes : 0.0;
  }

  r.mean_lancer = image_mean(image);
  // Lancer's error, where a reference is cached or can be made; Cycles' only with Cycles.
  const bool can_reference = o.reference == ReferenceFrom::Lancer || with_cycles;
  if (!can_reference && !fs::exists(reference_file(o, entry))) return r;
  ImageRGB ref;
  try {
    ref = reference_image(o, entry, bench, *accel, script, err);
    r.mean_ref = image_mean(ref);
    r.mse_lancer = mean_squared_error(image, ref);
  } catch (const std::exception& e) {
    r.cycles_failure = e.what();
    return r;
  }
  if (!with_cycles) return r;
  try {
    const fs::path cycles_file = o.cache / (entry.name + "-cycles-" + std::to_string(o.spp) + "spp.exr");
    std::vector<double> times;
    for (int rep = 0; rep < o.reps; ++rep) {
      times.push_back(run_cycles(o.blender, script, {entry.file, cycles_file, o.size, o.spp, o.max_depth, o.threads, 0}));
      err << "lancer bench --render: " << entry.name << ": Cycles " << rep + 1 << "/" << o.reps << " " << std::fixed
          << std::setprecision(2) << times.back() << " s\n";
    }
    r.cycles_s = median(times);
    const ImageRGB cycles = read_image(cycles_file);
    r.mse_cycles = mean_squared_error(cycles, ref);
    r.mean_cycles = image_mean(cycles);
    r.cycles = true;
  } catch (const std::exception& e) {
    r.cycles_failure = e.what();
  }
  return r;
}

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(3) << v;
  return s.str();
}

void write_table(const RenderBenchOptions& o, const std::vector<SceneResult>& results, std::ostream& out) {
  out << "Path tracer, " << o.size << "x" << o.size << ", " << o.spp << " spp, " << o.light_samples
      << " light sample(s) per bounce, max depth " << o.max_depth << ", "
      << (o.threads == 0 ? std::string("all") : std::to_string(o.threads)) << " thread(s), box filter, isa "
      << isa_name(best_supported_isa()) << "; times are medians of " << o.reps << " renders.\n\n";
  out << "| scene | triangles | Lancer s | paths/s | Mrays/s | rays/path | traversal share | MSE | 1 / (MSE x s) |\n"
         "|---|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const SceneResult& r : results) {
    if (!r.failure.empty()) {
      out << "| " << r.name << " | failed: " << r.failure << " | | | | | | | |\n";
      continue;
    }
    out << "| " << r.name << " | " << r.triangles << " | " << fixed(r.wall_s, 2) << " | " << fixed(r.paths_per_s, 0)
        << " | " << fixed(r.mrays_per_s, 2) << " | " << fixed(r.rays_per_path, 2) << " | "
        << fixed(100.0 * r.traversal_share, 1) << " %" << (r.replay_truncated ? " (part)" : "") << " | "
        << (r.mse_lancer > 0.0 ? sci(r.mse_lancer) + " | " + fixed(1.0 / (r.mse_lancer * (r.wall_s + r.build_s)), 0)
                               : std::string(" | "))
        << " |\n";
  }
  // Batches: per bounce of an 8x8 block, its continuation rays and its shadow rays.
  out << "\n| scene | continuation rays per batch | as packets | shadow rays per batch | as packets | "
         "shadow packets, ns/ray: packet / one by one |\n|---|--:|--:|--:|--:|--:|\n";
  for (const SceneResult& r : results) {
    if (!r.failure.empty()) continue;
    const PathBatchStats& b = r.batches;
    auto per = [](std::uint64_t n, std::uint64_t d) { return d > 0 ? static_cast<double>(n) / d : 0.0; };
    out << "| " << r.name << " | " << fixed(per(b.continuation_rays, b.continuation_batches), 1) << " | "
        << fixed(100.0 * per(b.packet_rays, b.continuation_rays), 1) << " % | "
        << fixed(per(b.shadow_rays, b.shadow_batches), 1) << " | "
        << fixed(100.0 * per(b.shadow_packet_rays, b.shadow_rays), 1) << " % | ";
    const std::uint64_t n = r.replay.any_packet_rays;
    if (n > 0)
      out << fixed(1e9 * r.replay.any_packet_s / double(n), 1) << " / "
          << fixed(1e9 * r.replay.any_packet_as_single_s / double(n), 1);
    out << " |\n";
  }
  const bool any_cycles = std::any_of(results.begin(), results.end(),
                                      [](const SceneResult& r) { return r.cycles || !r.cycles_failure.empty(); });
  out << "\nTraversal share: the render's tracer calls replayed alone on one thread, over its CPU time. MSE: "
         "against the " << (o.reference == ReferenceFrom::Cycles ? "Cycles" : "Lancer") << " reference of "
      << o.reference_spp << " spp, where one is cached or can be made.\n";
  if (!any_cycles) return;
  out << "\nBeside Blender Cycles (same file, camera, size, samples, bounces; errors against a "
      << (o.reference == ReferenceFrom::Cycles ? "Cycles" : "Lancer") << " render of " << o.reference_spp
      << " spp; Lancer's seconds include its kd-tree build, Cycles' its render call):\n\n"
      << "| scene | Lancer s | Cycles s | MSE Lancer | MSE Cycles | mean Lancer / Cycles / reference | "
         "speed at equal error, Lancer / Cycles |\n|---|--:|--:|--:|--:|--:|--:|\n";
  for (const SceneResult& r : results) {
    if (!r.cycles && r.cycles_failure.empty()) continue;
    if (!r.cycles) {
      out << "| " << r.name << " | Cycles failed: " << r.cycles_failure.substr(0, r.cycles_failure.find('\n'))
          << " | | | | | |\n";
      continue;
    }
    out << "| " << r.name << " | " << fixed(r.wall_s + r.build_s, 2) << " | " << fixed(r.cycles_s, 2) << " | "
        << sci(r.mse_lancer) << " | " << sci(r.mse_cycles) << " | " << fixed(r.mean_lancer, 4) << " / "
        << fixed(r.mean_cycles, 4) << " / " << fixed(r.mean_ref, 4) << " | **" << fixed(r.equal_error_ratio(), 2)
        << "x** |\n";
  }
}

void write_json(const RenderBenchOptions& o, const std::vector<SceneResult>& results, const std::string& file) {
  nlohmann::json j;
  j["size"] = o.size, j["spp"] = o.spp, j["max_depth"] = o.max_depth, j["threads"] = o.threads;
  j["light_samples"] = o.light_samples;
  j["isa"] = std::string(isa_name(best_supported_isa()));
  j["reference"] = o.reference == ReferenceFrom::Cycles ? "cycles" : "lancer";
  j["reference_spp"] = o.reference_spp;
  for (const SceneResult& r : results) {
    nlohmann::json s;
    s["scene"] = r.name;
    if (!r.failure.empty()) s["failure"] = r.failure;
    s["triangles"] = r.triangles, s["build_s"] = r.build_s, s["wall_s"] = r.wall_s, s["cpu_s"] = r.cpu_s;
    s["paths_per_s"] = r.paths_per_s, s["mrays_per_s"] = r.mrays_per_s, s["rays_per_path"] = r.rays_per_path;
    s["traversal_share"] = r.traversal_share;
    s["batches"] = {{"continuation_batches", r.batches.continuation_batches},
                    {"continuation_rays", r.batches.continuation_rays},
                    {"continuation_packet_rays", r.batches.packet_rays},
                    {"shadow_batches", r.batches.shadow_batches},
                    {"shadow_rays", r.batches.shadow_rays},
                    {"shadow_packet_rays", r.batches.shadow_packet_rays}};
    if (r.mse_lancer > 0.0) s["mse_lancer"] = r.mse_lancer;
    s["replay"] = {{"closest", r.replay.closest},     {"closest_s", r.replay.closest_s}, {"any", r.replay.any},
                   {"any_s", r.replay.any_s},         {"packet_rays", r.replay.packet_rays},
                   {"packet_s", r.replay.packet_s},   {"any_packet_rays", r.replay.any_packet_rays},
                   {"any_packet_s", r.replay.any_packet_s},
                   {"any_packet_as_single_s", r.replay.any_packet_as_single_s},
                   {"truncated", r.replay_truncated}};
    if (r.cycles) {
      s["cycles_s"] = r.cycles_s, s["mse_cycles"] = r.mse_cycles;
      s["equal_error_ratio"] = r.equal_error_ratio();
    } else if (!r.cycles_failure.empty()) {
      s["cycles_failure"] = r.cycles_failure;
    }
    j["scenes"].push_back(s);
  }
  std::ofstream f(file);
  f << j.dump(2) << "\n";
  if (!f) throw std::runtime_error("cannot write " + file);
}

}  // namespace

int run_render_bench(const RenderBenchOptions& o, const fs::path& scenes_dir, const fs::path& models_dir,
                     const fs::path& cycles_script, std::ostream& out, std::ostream& err) {
  const bool blender = o.cycles != CyclesUse::Off && blender_available(o.blender);
  if (o.cycles == CyclesUse::On && !blender) {
    err << "lancer bench --render: --cycles on, but " << o.blender << " cannot be run (Debian: apt-get install blender)\n";
    return 2;
  }
  if (o.cycles == CyclesUse::Auto && !blender)
    err << "lancer bench --render: " << o.blender << " not found: Lancer only, no Cycles comparison\n";
  int status = 0;
  std::vector<SceneResult> results;
  for (const std::string& name : o.scenes.empty() ? render_suite_names() : o.scenes) {
    try {
      const SuiteScene entry = resolve(name, scenes_dir, models_dir);
      if (entry.kind == SuiteScene::Kind::File && !fs::exists(entry.file)) {
        err << "lancer bench --render: " << name << ": skipped, " << entry.file.string() << " not found\n";
        continue;
      }
      results.push_back(measure(o, entry, blender && entry.kind == SuiteScene::Kind::File && is_gltf(entry.file),
                                cycles_script, err));
      if (!results.back().cycles_failure.empty()) {
        err << "lancer bench --render: " << name << ": " << results.back().cycles_failure << "\n";
        status = 1;
      }
    } catch (const UnknownScene& e) {
      err << "lancer bench --render: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      SceneResult failed;
      failed.name = name;
      failed.failure = e.what();
      results.push_back(failed);
      err << "lancer bench --render: " << name << ": " << e.what() << "\n";
      status = 1;
    }
  }
  write_table(o, results, out);
  if (!o.json.empty()) {
    write_json(o, results, o.json);
    err << "lancer bench --render: wrote " << o.json << "\n";
  }
  return status;
}

}  // namespace lancer::bench
