#include "app/cli.h"

#include "dist/launch.h"


#include <algorithm>
#include <new>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "accel/accel_factory.h"
#include "app/bench_command.h"
#include "app/gen_command.h"
#include "app/info_command.h"
#include "app/rays_command.h"
#include "app/render_command.h"
#include "app/start_threads.h"
#include "app/trace_command.h"
#include "render/caustic_map.h"
#include "render/sppm_render.h"
#include "simd/isa.h"
#include "simd/out_of_memory.h"

namespace lancer {

namespace {

// "x,y,z" -> vec3, for --eye, --look-at and --up.
void add_vec3_option(CLI::App& app, const std::string& name, std::optional<glm::vec3>& target,
                     const std::string& help) {
  app.add_option_function<std::vector<float>>(
         name, [&target](const std::vector<float>& v) { target = glm::vec3(v[0], v[1], v[2]); }, help)
      ->expected(3)
      ->delimiter(',')
      ->type_name("X,Y,Z");
}

void add_kd_split_option(CLI::App& app, std::string& split) {
  std::vector<std::string> names;
  for (auto n : kd_split_names()) names.emplace_back(n);
  app.add_option("--kd-split", split, "kd-tree split strategy: sah, or the naive middle and median")
      ->check(CLI::IsMember(names))->capture_default_str();
}

void add_isa_option(CLI::App& app, std::string& isa) {
  app.add_option("--isa", isa, "Instruction set for the kd-tree kernels and the path tracer's vector passes: scalar, sse4, avx2 or avx512")
      ->check(CLI::IsMember({"scalar", "sse4", "avx2", "avx512"}))
      ->default_str(std::string(isa_name(best_supported_isa())) + " (the best this CPU runs)");
}

void add_instancing_option(CLI::App& app, InstancingMode& mode) {
  app.add_option_function<std::string>(
         "--instancing",
         [&mode](const std::string& name) {
           mode = name == "on" ? InstancingMode::On : name == "off" ? InstancingMode::Off : InstancingMode::Auto;
         },
         "glTF meshes drawn more than once: stored once and drawn through instances (two-level kd-tree) when the "
         "copies would add 65536 triangles (auto), whenever drawn twice (on), or copied (off)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->default_str("auto");
}

void add_render_command(CLI::App& app, RenderOptions& opt) {
  CLI::App* render = app.add_subcommand("render", "Render a scene to image files");
  render->add_option("scene", opt.scene, "Scene file (.gltf, .glb or .obj)")->required();
  render->add_option("-o,--output", opt.outputs, "Output image (.exr linear float, .png sRGB); repeatable")
      ->default_str("out/render.exr and out/render.png");
  render->add_option("--exposure", opt.display.exposure_ev,
                     "PNG output: exposure in stops, the image times 2^EV before the tone curve (EXR stays linear)")
      ->check(CLI::Range(-64.0f, 64.0f))
      ->capture_default_str();
  render->add_option_function<std::string>(
            "--tone",
            [&opt](const std::string& name) {
              if (!parse_tone_curve(name, opt.display.curve)) throw CLI::ValidationError("--tone", "unknown curve");
            },
            "PNG output tone curve: neutral (Khronos PBR Neutral: colours kept up to 0.76, highlights rolled off) or "
            "clamp (exact up to 1, white above)")
      ->check(CLI::IsMember({"neutral", "clamp"}))
      ->default_str("neutral");
  RenderSettings& s = opt.settings;
  render->add_option("--width", s.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  render->add_option_function<int>(
            "--height", [&opt](int h) { opt.settings.height = h; opt.height_given = true; },
            "Image height in pixels (default: from the camera's aspect ratio, else the width)")
      ->check(CLI::Range(1, 16384));
  render->add_option_function<int>(
            "--spp", [&opt](int spp) { opt.settings.spp = spp; opt.spp_given = true; },
            "Jittered samples per pixel (with --time: at most this many)")
      ->check(CLI::Range(1, 1 << 20))
      ->default_str(std::to_string(s.spp));
  render->add_option("--time", opt.time_limit_s,
                     "Render for this many seconds (as many samples per pixel as fit, up to --spp when given); "
                     "the image is written when the time is up")
      ->check(CLI::Range(0.001, 1e7))->type_name("SECONDS");
  render->add_option("--checkpoint", opt.checkpoint_s,
                     "Also write the outputs every this many seconds while rendering (after a full pass)")
      ->check(CLI::Range(0.001, 1e7))->type_name("SECONDS");
  render->add_option("--resume", opt.resume,
                     "Continue the render saved in this EXR output (a checkpoint, or the image an interrupted or "
                     "shorter render wrote) with the same scene and settings; --spp may be raised. The image ends "
                     "bit-identical to an uninterrupted render's (not for sppm)")
      ->type_name("FILE.exr");
  s.integrator = IntegratorKind::Path;
  render->add_option_function<std::string>(
            "--integrator", [&s](const std::string& name) { s.integrator = *parse_integrator(name); },
            "path (physically based), sppm (stochastic progressive photon mapping: path tracing plus photons for "
            "caustics; --spp counts iterations), photon (the path tracer plus Jensen's caustic photon map, shot "
            "once before the passes), whitted (recursive ray tracing), or the debug views normals, albedo, depth, "
            "ao (ambient occlusion), primid")
      ->check(CLI::IsMember({"path", "sppm", "photon", "whitted", "normals", "albedo", "depth", "ao", "primid"}))
      ->default_str("path");
  render->add_option("--photons", s.photons,
                     "sppm: photons shot per iteration (default: one per pixel, at most 4194304); photon: caustic "
                     "photons shot in all (default: four per pixel, at least 200000, at most 4194304)")
      ->check(CLI::Range(std::int64_t(1), std::max(kMaxPhotonsPerIteration, kMaxCausticPhotons)));
  render->add_option("--caustic-k", s.caustic_k,
                     "photon: the photons nearest to a point that estimate its caustic (default: 50)")
      ->check(CLI::Range(2, kMaxCausticK));
  render->add_option("--caustic-radius", s.caustic_radius,
                     "photon: the largest radius the nearest photons are searched within, in scene units (default: "
                     "1/20 of the radius of the scene's bounding sphere)")
      ->check(CLI::Range(1e-30, 1e30))->type_name("RADIUS");
  render->add_option("--sppm-radius", s.sppm_radius,
                     "sppm: the gather radius every pixel starts with, in scene units (default: 3 pixel footprints "
                     "at the distance of the pixel's first visible point)")
      ->check(CLI::Range(1e-30, 1e30))->type_name("RADIUS");
  render->add_option("--env", opt.env_file,
                     "Environment: an equirectangular map (.exr, .hdr, .png) lighting the scene (path, sppm and photon "
                     "only; "
                     "default: black)")
      ->type_name("FILE");
  render->add_option("--env-color", opt.env_color, "Environment: a constant colour R,G,B (linear radiance)")
      ->expected(3)->delimiter(',')->type_name("R,G,B");
  render->add_option("--env-scale", opt.env_scale, "Multiplies the environment's radiance")
      ->check(CLI::Range(0.0, 1e30))->capture_default_str();
  render->add_option_function<std::string>(
            "--filter", [&s](const std::string& name) {
              s.filter = name == "gaussian" ? PixelFilterType::Gaussian : PixelFilterType::Box;
            },
            "Pixel filter: box (jitter over the pixel) or gaussian (sigma 0.5 px, radius 1.5 px)")
      ->check(CLI::IsMember({"box", "gaussian"}))
      ->default_str("box");
  render->add_option("--aperture", opt.aperture, "Thin-lens aperture radius in scene units (0: pinhole)")
      ->check(CLI::Range(0.0, 1e30));
  render->add_option("--focus-distance", opt.focus_distance, "Distance to the plane in focus, along the view axis")
      ->check(CLI::Range(1e-30, 1e30));
  render->add_option_function<std::string>(
            "--mode", [&s](const std::string& name) { s.mode = *parse_trace_mode(name); },
            "Primary rays: packet (8x8 pixel blocks traced together) or single (one ray at a time); "
            "the image is the same")
      ->check(CLI::IsMember({"packet", "single"}))
      ->default_str("packet");
  render->add_option("--max-depth", s.max_depth,
                     "path, sppm, photon: bounces after the camera ray; whitted: reflection and refraction recursion "
                     "limit")
      ->check(CLI::Range(0, 64))->capture_default_str();
  render->add_option("--light-samples", s.light_samples,
                     "Points sampled on the emissive triangles per shading point, each with a shadow ray (path: at "
                     "every bounce, combined with BSDF sampling by MIS, as for photon; sppm: at each camera path's "
                     "non-delta "
                     "vertex; whitted: at each diffuse hit)")
      ->check(CLI::Range(1, 4096))->capture_default_str();
  render->add_option("--threads", s.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  render->add_option("--seed", s.seed, "Random seed; the image depends only on it, not on threads")->capture_default_str();
  std::vector<std::string> accels;
  for (auto n : accelerator_names()) accels.emplace_back(n);
  render->add_option("--accel", opt.accel, "Accelerator: kdtree, or brute (the scalar oracle)")
      ->check(CLI::IsMember(accels))->capture_default_str();
  add_kd_split_option(*render, opt.kd_split);
  add_isa_option(*render, opt.isa);
  render->add_option("--camera", opt.camera,
                     "Number of the glTF camera to use, as in the file's cameras (default: the first the scene places)")
      ->check(CLI::NonNegativeNumber);
  render->add_option("--scene", opt.gltf_scene, "Number of the glTF scene to render (default: the file's default scene)")
      ->check(CLI::NonNegativeNumber);
  add_instancing_option(*render, opt.instancing);
  render->add_option_function<std::vector<double>>(
             "--shutter", [&opt](const std::vector<double>& v) { opt.shutter = v; },
             "Motion blur: the shutter open from OPEN to CLOSE seconds on the first animation's timeline; what "
             "moves then is blurred (path, whitted and debug integrators)")
      ->expected(2)
      ->delimiter(',')
      ->type_name("OPEN,CLOSE");
  render->add_option("--frame-time", opt.frame_time,
                     "Pose an animated glTF file as its first animation has it at this time, in seconds (default: "
                     "each channel's first keyframe; held before the first and after the last)");
  add_vec3_option(*render, "--eye", opt.eye, "Camera position (overrides the scene camera)");
  add_vec3_option(*render, "--look-at", opt.look_at, "Point the camera looks at");
  add_vec3_option(*render, "--up", opt.up, "Camera up direction (default 0,1,0)");
  render->add_option("--fov", opt.fov_degrees, "Vertical field of view in degrees")->check(CLI::Range(0.01, 179.0));
  render->add_flag_function(
      "--no-progress", [&opt](std::int64_t) { opt.progress = false; }, "Do not report progress on stderr");
}

void add_info_command(CLI::App& app, InfoOptions& opt) {
  CLI::App* info = app.add_subcommand("info", "Print what a scene holds and accelerator statistics");
  info->add_option("scene", opt.scene, "Scene file (.gltf, .glb or .obj)")->required();
  std::vector<std::string> accels;
  for (auto n : accelerator_names()) accels.emplace_back(n);
  info->add_option("--scene", opt.gltf_scene, "Number of the glTF scene to describe (default: the file's default scene)")
      ->check(CLI::NonNegativeNumber);
  info->add_option("--accel", opt.accel, "Accelerator to build and describe")->check(CLI::IsMember(accels))->capture_default_str();
  add_kd_split_option(*info, opt.kd_split);
  add_isa_option(*info, opt.isa);
  add_instancing_option(*info, opt.instancing);
}

void add_trace_command(CLI::App& app, TraceOptions& opt) {
  CLI::App* trace = app.add_subcommand(
      "trace", "Trace the rays of a ray file on a scene, write the answers and print Mrays/s (docs/ray-files.md)");
  trace->add_option("scene", opt.scene, "Scene file (.gltf, .glb or .obj)")->required();
  trace->add_option("--rays", opt.rays, "Ray file: 8 little-endian float32 per ray, ox oy oz tnear dx dy dz tfar")
      ->required()->type_name("FILE");
  trace->add_option("--hits", opt.hits,
                    "Output: per ray float32 t (+inf: none) and uint32 source triangle id (0xFFFFFFFF: none); "
                    "with --occlusion one byte per ray (1: occluded)")
      ->required()->type_name("OUT");
  trace->add_option_function<std::string>(
           "--mode", [&opt](const std::string& name) { opt.mode = *parse_trace_mode(name); },
           "packet (each run of 64 consecutive rays traced as one packet, whatever they hold) or single (one "
           "ray at a time); the answers are the same")
      ->check(CLI::IsMember({"packet", "single"}))
      ->default_str("packet");
  add_isa_option(*trace, opt.isa);
  add_instancing_option(*trace, opt.instancing);
  trace->add_option("--threads", opt.threads, "Worker threads (0: all cores); the answers do not depend on it")
      ->check(CLI::Range(0, 4096))->capture_default_str();
  trace->add_flag("--occlusion", opt.occlusion,
                  "Answer occluded-or-not instead of the closest hit: occlusion packets of 64 consecutive rays "
                  "(--mode packet, each ray leaving at its first hit) or one occluded() call per ray (single)");
}

void add_rays_command(CLI::App& app, RaysOptions& opt) {
  CLI::App* rays = app.add_subcommand(
      "rays", "Write a standard ray set of a scene to a ray file, in 8x8 pixel-tile order (docs/ray-files.md)");
  rays->add_option("scene", opt.scene, "Scene file (.gltf, .glb or .obj)")->required();
  rays->add_option_function<std::string>(
          "--set", [&opt](const std::string& name) { opt.set = *parse_ray_set(name); },
          "primary (camera rays through the pixel centres), diffuse (one cosine-weighted bounce per primary "
          "hit) or shadow (one ray per primary hit toward a point on the lights)")
      ->required()
      ->check(CLI::IsMember({"primary", "diffuse", "shadow"}));
  rays->add_option("-o,--output", opt.output, "Ray file to write")->required()->type_name("FILE");
  const CLI::Validator multiple_of_tile(
      [](std::string& value) -> std::string {
        try {
          if (std::stoi(value) % kRayTileSide == 0) return {};
        } catch (const std::exception&) {
        }
        return "must be a multiple of " + std::to_string(kRayTileSide);
      },
      "MULTIPLE OF 8");
  rays->add_option("--width", opt.width, "Image width in pixels, a multiple of 8")
      ->check(CLI::Range(8, 16384))->check(multiple_of_tile)->capture_default_str();
  rays->add_option("--height", opt.height, "Image height in pixels, a multiple of 8")
      ->check(CLI::Range(8, 16384))->check(multiple_of_tile)->capture_default_str();
  rays->add_option("--seed", opt.seed, "Random seed of the diffuse and shadow sets")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
}

void add_gen_command(CLI::App& app, GenOptions& opt) {
  CLI::App* gen = app.add_subcommand("gen", "Write a generated scene: Eric Haines' Standard Procedural Databases");
  gen->add_option("kind", opt.kind, "Generator family (spd: the Standard Procedural Databases, 1987)")
      ->required()->check(CLI::IsMember({"spd"}));
  gen->add_option("name", opt.name, "SPD scene: balls, gears, mount, rings or tetra")
      ->required()->check(CLI::IsMember({"balls", "gears", "mount", "rings", "tetra"}));
  gen->add_option("-s,--size", opt.size,
                  "SPD size factor: balls 0..6 (recursion depth), gears 1..44 (gears per side), mount 0..12 "
                  "(fractal depth), rings 1..50 (pyramid layers), tetra 1..12 (depth)")
      ->required();
  gen->add_option("-o,--output", opt.output, "Output binary glTF file (.glb)")->required()->type_name("FILE");
  gen->add_option("--sphere-subdivisions", opt.tessellation.sphere_subdivisions,
                  "Icosphere subdivisions per sphere, 20*4^S triangles each (balls, mount, rings)")
      ->check(CLI::Range(0, 8))->capture_default_str();
  gen->add_option("--cylinder-sides", opt.tessellation.cylinder_sides,
                  "Sides per capped cylinder, 4*K triangles each (rings)")
      ->check(CLI::Range(3, 1024))->capture_default_str();
}

// Everything after `bench` goes to lancer-bench untouched, --help included.
CLI::App* add_bench_command(CLI::App& app) {
  CLI::App* bench = app.add_subcommand(
      "bench", "Benchmark Lancer beside Embree 3 (runs lancer-bench; `lancer bench --help` for its options)");
  bench->prefix_command();
  bench->allow_extras();
  bench->set_help_flag();
  return bench;
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"Lancer: a CPU ray tracer (lancer de rayons)", "lancer"};
  app.require_subcommand(1);
  RenderOptions render_opt;
  InfoOptions info_opt;
  TraceOptions trace_opt;
  RaysOptions rays_opt;
  GenOptions gen_opt;
  add_render_command(app, render_opt);
  add_info_command(app, info_opt);
  add_trace_command(app, trace_opt);
  add_rays_command(app, rays_opt);
  add_gen_command(app, gen_opt);
  CLI::App* bench = add_bench_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();  // the selected subcommand's help when one was given
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ParseError& e) {
    if (mpirun_rank() == 0) {  // under mpirun every rank parses the same line: one says so
      err << "lancer: " << e.what() << "\n";
      err << "Run 'lancer --help' or 'lancer render --help' for the options.\n";
    }
    return 2;
  }
  if (mpirun_world_size() > 1 && !app.get_subcommand("render")->parsed()) {
    if (mpirun_rank() == 0)
      err << "lancer: error: under mpirun only 'lancer render' runs as one job over several ranks; run the others "
             "without mpirun\n";
    return 2;
  }

  if (app.got_subcommand(bench)) return run_bench(bench->remaining(), err);
  try {
    const bool rendering = app.get_subcommand("render")->parsed();
    start_worker_threads(rendering                          ? render_opt.settings.threads
                         : app.got_subcommand("trace") ? trace_opt.threads
                                                           : 0);
  } catch (const std::bad_alloc& e) {
    err << "lancer: error: " << out_of_memory_message(e) << " starting the worker threads\n";
    return 1;
  } catch (const std::exception& e) {
    err << "lancer: error: could not start the worker threads: " << e.what() << "\n";
    return 1;
  }
  if (CLI::App* render = app.get_subcommand("render"); render->parsed()) {
    for (const CLI::Option* o : render->get_options())
      if (o->count() > 0 && !o->get_lnames().empty()) render_opt.given.push_back("--" + o->get_lnames().front());
    return run_render(render_opt, out, err);
  }
  if (app.got_subcommand("trace")) return run_trace(trace_opt, out, err);
  if (app.got_subcommand("rays")) return run_rays(rays_opt, out, err);
  if (app.got_subcommand("gen")) return run_gen(gen_opt, out, err);
  return run_info(info_opt, out, err);
}

}  // namespace lancer
