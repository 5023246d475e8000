#include "app/render_command.h"

#include <unistd.h>

#include <array>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <ostream>

#include "accel/accel_factory.h"
#include "app/camera_choice.h"
#include "app/interrupt.h"
#include "app/progress_reporter.h"
#include "app/resume.h"
#include "dist/distributed_render.h"
#include "dist/launch.h"
#include "render/camera.h"
#include "render/checkpoint_file.h"
#include "render/content_hash.h"
#include "render/environment.h"
#include "render/image_io.h"
#include "render/renderer.h"
#include "render/sample_renderer.h"
#include "scene/load_scene.h"
#include "scene/scene_error.h"
#include "simd/out_of_memory.h"

namespace lancer {

namespace {

// Images larger than this are refused before any allocation (2^28 pixels = 3 GiB of RGB floats).
constexpr long long kMaxPixels = 1LL << 28;
// Passes a --time render may make (the most --spp accepts).
constexpr int kMaxSpp = 1 << 20;

bool has_light(const Scene& scene) {
  if (!scene.lights.empty()) return true;
  for (std::uint32_t id : scene.material_id)
    if (scene.materials[id].emissive()) return true;
  return false;
}

}  // namespace

std::optional<std::string> integrator_ignores(IntegratorKind integrator, const std::vector<std::string>& given) {
  const bool sppm = integrator == IntegratorKind::Sppm, photon = integrator == IntegratorKind::Photon;
  const bool paths = integrator == IntegratorKind::Path || sppm || photon;  // lit by the environment too
  const bool lit = paths || integrator == IntegratorKind::Whitted;
  for (const std::string& option : given) {
    const bool needs_lit = option == "--max-depth" || option == "--light-samples";
    const bool needs_env = option == "--env" || option == "--env-color" || option == "--env-scale";
    const bool needs_photons = option == "--photons";
    const bool needs_sppm = option == "--sppm-radius";
    const bool needs_photon = option == "--caustic-k" || option == "--caustic-radius";
    if ((needs_lit && !lit) || (needs_env && !paths) || (needs_photons && !sppm && !photon) || (needs_sppm && !sppm) ||
        (needs_photon && !photon))
      return option;
  }
  return std::nullopt;
}

void print_load_warnings(const Scene& scene, std::ostream& err) {
  if (scene.stats.degenerate_dropped > 0)
    err << "lancer: warning: " << scene.source << ": dropped " << scene.stats.degenerate_dropped
        << " zero-area triangle(s)\n";
  if (scene.stats.zero_normals_repaired > 0)
    err << "lancer: warning: " << scene.source << ": " << scene.stats.zero_normals_repaired
        << " zero-length normal(s); those triangles use their geometric normal\n";
}

KdBuildOptions kd_options_from(const std::string& split) {
  KdBuildOptions kd;
  const auto parsed = parse_kd_split(split);
  if (!parsed) throw std::invalid_argument("unknown kd-tree split '" + split + "'");
  kd.split = *parsed;
  return kd;
}

Isa isa_from(const std::string& name) {
  if (name.empty()) return best_supported_isa();
  const auto isa = parse_isa(name);
  if (!isa) throw std::invalid_argument("unknown ISA '" + name + "' (expected scalar, sse4, avx2 or avx512)");
  if (!cpu_supports(*isa)) throw std::invalid_argument("--isa " + name + ": this CPU (or its operating system) does not support it");
  return *isa;
}

namespace {

std::string host_name() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0) return "?";
  return name.data();
}

}  // namespace

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err) {
  // Under mpirun: one of several ranks of one render (dist/distributed_render.h). Rank 0
  // does what a single process does; the others load the scene, build the tree and render
  // what rank 0 hands them, and write nothing.
  std::unique_ptr<Channel> channel;
  try {
    channel = open_mpi_channel();
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
    return 1;
  }
  const int rank = channel ? channel->rank() : 0;
  bool distributed_started = false;  // past every rank's setup
  RenderSettings worker_settings;    // for a worker whose setup failed
  std::string failure;
  try {
    RenderOptions opt = options;
    if (const auto ignored = integrator_ignores(opt.settings.integrator, opt.given))
      throw std::invalid_argument(*ignored + ": the " + std::string(integrator_name(opt.settings.integrator)) +
                                  " integrator does not use it" +
                                  (ignored->rfind("--env", 0) == 0
                                       ? " (the environment lights only --integrator path, sppm and photon)"
                                       : ""));
    if (opt.outputs.empty()) opt.outputs = {"out/render.exr", "out/render.png"};
    for (const auto& o : opt.outputs) {
      std::string ext = std::filesystem::path(o).extension().string();
      for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".exr" && ext != ".png")
        throw std::invalid_argument("output " + o + ": unknown image type '" + ext + "' (expected .exr or .png)");
    }

    if (channel && opt.settings.integrator == IntegratorKind::Sppm)  // before every rank loads the scene
      throw std::invalid_argument("--integrator sppm renders in one process (each photon pass spans the whole "
                                  "image); run it without mpirun");
    // Read first, so a wrong file is refused before the scene loads.
    std::optional<Checkpoint> resumed;
    if (!opt.resume.empty() && rank == 0) {  // (the workers keep no state)
      if (opt.settings.integrator == IntegratorKind::Sppm)
        throw std::invalid_argument("--resume: the sppm integrator cannot resume a render (its photon statistics are "
                                    "not saved); render it again, with --time or a larger --spp");
      resumed = read_checkpoint(opt.resume);
    }

    const auto t_load = std::chrono::steady_clock::now();
    if ((opt.settings.integrator == IntegratorKind::Sppm || opt.settings.integrator == IntegratorKind::Photon) &&
        opt.shutter)
      throw std::invalid_argument("--shutter: motion blur works with the path, whitted and debug integrators, not " +
                                  std::string(integrator_name(opt.settings.integrator)));
    const std::optional<Shutter> shutter =
        opt.shutter ? std::optional<Shutter>(Shutter{opt.shutter->at(0), opt.shutter->at(1)}) : std::nullopt;
    const Scene scene = load_scene(opt.scene, opt.gltf_scene, opt.frame_time, opt.instancing, shutter);
    if (rank == 0 && shutter && scene.instancing.motions.empty())
      err << "lancer: warning: " << scene.source << ": nothing moves while the shutter is open (--shutter "
          << shutter->open << "," << shutter->close << "): the image is a still\n";
    if (rank == 0) print_load_warnings(scene, err);  // (every rank loads the same scene: one says so)
    const bool lit_by_env = !opt.env_file.empty() || !opt.env_color.empty();
    if (rank == 0 && !has_light(scene) && !lit_by_env &&
        (opt.settings.integrator == IntegratorKind::Whitted || opt.settings.integrator == IntegratorKind::Path ||
         opt.settings.integrator == IntegratorKind::Sppm || opt.settings.integrator == IntegratorKind::Photon))
      err << "lancer: warning: " << scene.source << ": the scene has no lights; the image will be black ("
          << (opt.settings.integrator != IntegratorKind::Whitted
                  ? "light it with --env-color R,G,B, a constant sky, or --env FILE, an environment map"
                  : "give it an emissive material or a punctual light, or render with --integrator path "
                    "--env-color R,G,B")
          << ")\n";

    RenderSettings& s = opt.settings;
    PinholeCamera camera =
        choose_camera({opt.camera, opt.eye, opt.look_at, opt.up, opt.fov_degrees}, scene, s.width, s.height,
                      opt.height_given);
    camera.set_shutter_open(shutter && shutter->close > shutter->open);
    if (opt.aperture || opt.focus_distance)
      camera.set_thin_lens(opt.aperture.value_or(camera.aperture_radius()),
                           opt.focus_distance.value_or(camera.focus_distance()));
    std::unique_ptr<Environment> environment;
    if (!opt.env_file.empty() && !opt.env_color.empty())
      throw std::invalid_argument("--env and --env-color: give one environment, not both");
    if (!opt.env_file.empty()) environment = std::make_unique<Environment>(opt.env_file, opt.env_scale);
    if (!opt.env_color.empty())
      environment = std::make_unique<Environment>(
          opt.env_scale * glm::vec3(opt.env_color[0], opt.env_color[1], opt.env_color[2]));
    s.environment = environment.get();
    if (static_cast<long long>(s.width) * s.height > kMaxPixels)
      throw std::invalid_argument("image " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                  " is too large (at most 2^28 pixels)");

    const Isa isa = isa_from(opt.isa);
    if (!opt.isa.empty()) s.vector_isa = isa;  // the path tracer's vector passes follow --isa too
    const auto t_build = std::chrono::steady_clock::now();
    const std::unique_ptr<Accelerator> accel = make_accelerator(opt.accel, scene.triangles, scene.instancing, kd_options_from(opt.kd_split), isa);
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_build).count();
    const double load_s = std::chrono::duration<double>(t_build - t_load).count();

    // --time without --spp: as many passes as the time allows.
    if (opt.time_limit_s > 0.0 && !opt.spp_given) s.spp = kMaxSpp;
    // Every EXR output but sppm's carries the exact render state, so it can be resumed.
    RenderState state;
    const bool keeps_state = s.integrator != IntegratorKind::Sppm;
    CheckpointFacts facts;
    if (resumed) {
      state = take_resumed_state(std::move(*resumed), opt, s, scene, camera, kMaxSpp, facts);
    } else if (keeps_state && rank == 0) {
      facts = render_facts(opt, s, scene, camera);
    }
    if (rank == 0)
      for (const auto& o : opt.outputs) {
        const std::filesystem::path parent = std::filesystem::path(o).parent_path();
        if (!parent.empty()) std::filesystem::create_directories(parent);
      }
    // The EXRs first: they are what a resume needs, should the process be killed while it
    // writes (mpirun sends SIGKILL about a second after SIGTERM).
    auto write_outputs = [&](const ImageRGB& image) {
      for (const bool exr_pass : {true, false})
        for (const auto& o : opt.outputs) {
          std::string ext = std::filesystem::path(o).extension().string();
          for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
          if ((ext == ".exr") != exr_pass) continue;
          if (keeps_state && ext == ".exr") write_checkpoint(state, facts, o);
          else write_image(image, o, opt.display);
        }
    };

    const InterruptGuard interrupt;
    RenderControl control;
    control.stop = &interrupt.flag();
    control.time_limit_s = opt.time_limit_s;
    control.checkpoint_s = opt.checkpoint_s;
    if (keeps_state) control.state = &state;
    control.on_checkpoint = [&](const ImageRGB& image, int) { write_outputs(image); };
    ProgressReporter progress(err, opt.progress && isatty(STDERR_FILENO));
    const auto t_render = std::chrono::steady_clock::now();
    RenderStats stats;
    auto report_progress = [&](std::size_t done, std::size_t total) {
      if (!opt.progress) return;
      if (opt.time_limit_s > 0.0 && !opt.spp_given) {  // progress is the time used
        const double used = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_render).count();
        progress.update(static_cast<std::size_t>(std::min(used, opt.time_limit_s) * 1000.0),
                        static_cast<std::size_t>(opt.time_limit_s * 1000.0));
      } else {
        progress.update(done, total);
      }
    };
    ImageRGB image;
    DistributedReport report;
    if (channel) {
      worker_settings = s;
      check_render_settings(scene, camera, s);
      TileRunner runner(s.threads);
      const SampleRenderer renderer(scene, *accel, camera, s, runner);
      // What every rank must agree on (not spp: only rank 0 reads a resumed render's).
      ContentHash digest;
      for (const auto& [key, value] : render_facts(opt, s, scene, camera))
        if (key != "spp") digest.add(key + "=" + value + "\n");
      const WorkerReady me{true, runner.concurrency(), load_s, build_s, host_name(), "", digest.hex()};
      distributed_started = true;
      if (rank != 0) {
        serve_distributed(*channel, &renderer, s, &runner, me);
        return 0;
      }
      image = render_distributed(*channel, renderer, s, runner, me, state, stats, report, report_progress, control);
    } else {
      image = render_image(scene, *accel, camera, s, stats, report_progress, control);
    }
    progress.finish();

    if (const std::size_t bad = count_non_finite(image); bad > 0)
      err << "lancer: warning: " << bad << " pixel(s) are not finite\n";
    write_outputs(image);

    char line[1024];
    const double mrays = stats.seconds > 0.0 ? static_cast<double>(stats.rays) / stats.seconds * 1e-6 : 0.0;
    // Primary rays per second of one thread's time inside the camera-ray tracing calls: the
    // number that compares packet and single mode, free of shading and thread count.
    const double primary_mrays =
        stats.primary_seconds > 0.0 ? static_cast<double>(stats.primary_rays) / stats.primary_seconds * 1e-6 : 0.0;
    std::snprintf(line, sizeof line,
                  "lancer: %s %dx%d, %d spp, %s, accel %s, isa %s, mode %s (%zu triangles drawn): load %.2f s, "
                  "build %.2f s, render %.2f s, %.2f Mrays, %.2f Mrays/s, primary %.2f Mrays/s/thread",
                  scene.source.c_str(), s.width, s.height, stats.stopped ? static_cast<int>(stats.max_spp) : s.spp,
                  std::string(integrator_name(s.integrator)).c_str(),
                  opt.accel.c_str(), std::string(isa_name(opt.accel == "brute" ? Isa::Scalar : isa)).c_str(),
                  std::string(trace_mode_name(s.mode)).c_str(), scene.drawn_triangle_count(), load_s, build_s,
                  stats.seconds, static_cast<double>(stats.rays) * 1e-6, mrays, primary_mrays);
    out << line << "\n";
    if (channel) {
      double load_lo = 1e300, load_hi = 0.0, build_lo = 1e300, build_hi = 0.0;
      int threads_lo = 1 << 30, threads_hi = 0;
      for (const WorkerReady& r : report.ranks) {
        load_lo = std::min(load_lo, r.load_s), load_hi = std::max(load_hi, r.load_s);
        build_lo = std::min(build_lo, r.build_s), build_hi = std::max(build_hi, r.build_s);
        threads_lo = std::min(threads_lo, r.threads), threads_hi = std::max(threads_hi, r.threads);
      }
      std::snprintf(line, sizeof line,
                    "lancer: %d ranks x %d%s thread(s): each loaded the scene in %.2f-%.2f s and built its tree in "
                    "%.2f-%.2f s; %zu work units of up to %d pass(es)",
                    channel->size(), threads_lo,
                    threads_hi != threads_lo ? ("-" + std::to_string(threads_hi)).c_str() : "", load_lo, load_hi,
                    build_lo, build_hi, report.units, report.largest_unit);
      out << line << "\n";
      for (const std::string& w : report.warnings) err << "lancer: warning: " << w << "\n";
    }
    if (stats.stopped)
      out << "lancer: " << (interrupt.exit_code() != 0 ? "interrupted" : "time limit reached") << " after "
          << stats.passes << " full pass(es); pixels have " << stats.min_spp << " to " << stats.max_spp
          << " samples\n";
    for (const auto& o : opt.outputs) out << "wrote " << o << "\n";
    return interrupt.exit_code();
  } catch (const WorkerSetupFailed& e) {  // every rank has stopped in order
    err << "lancer: error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc& e) {
    failure = out_of_memory_message(e);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  if (!channel) {
    err << "lancer: error: " << failure << "\n";
    return 1;
  }
  // A distributed render that failed: before the render starts, every rank learns it and
  // stops in order (rank 0 reports, the workers tell rank 0); in the middle of it, the
  // failing rank ends the job (rank 0 saves what it has on the runtime's SIGTERM).
  if (rank == 0 || distributed_started)
    err << "lancer: " << (rank == 0 ? std::string() : "rank " + std::to_string(rank) + " on " + host_name() + ": ")
        << "error: " << failure << "\n";
  if (distributed_started) channel->abort(1);
  try {
    if (rank == 0) {
      abandon_distributed(*channel);
    } else {
      WorkerReady me;
      me.ok = false, me.host = host_name(), me.error = failure;
      serve_distributed(*channel, nullptr, worker_settings, nullptr, me);
    }
  } catch (const std::exception& e) {
    err << "lancer: error: " << e.what() << "\n";
    channel->abort(1);
  }
  return 1;
}

}  // namespace lancer
