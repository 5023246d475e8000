// `lancer render`: load a scene, build the accelerator, render, write the images.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "accel/kd_build.h"
#include "simd/isa.h"
#include "render/display.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace lancer {

struct RenderOptions {
  std::string scene;
  std::vector<std::string> outputs;  // by extension: .exr, .png
  DisplayTransform display{0.0f, ToneCurve::Neutral};  // --exposure, --tone (PNG only)
  RenderSettings settings;
  bool height_given = false;
  std::string accel = "kdtree";
  std::string kd_split = "sah";
  std::string isa;  // empty: the best this CPU supports
  std::optional<int> camera;         // glTF camera index
  std::optional<int> gltf_scene;     // --scene: glTF scene index
  std::optional<double> frame_time;  // --frame-time: seconds on the animation's timeline
  std::optional<std::vector<double>> shutter;  // --shutter OPEN,CLOSE: seconds on that timeline
  InstancingMode instancing = InstancingMode::Auto;  // --instancing
  std::optional<glm::vec3> eye, look_at, up;
  std::optional<float> fov_degrees;  // vertical
  bool progress = true;
  bool spp_given = false;       // --spp on the command line (else --time renders until its limit)
  double time_limit_s = 0.0;    // --time: stop after this many seconds (0: none)
  double checkpoint_s = 0.0;    // --checkpoint: write the outputs this often (0: never)
  std::string resume;           // --resume: continue the render saved in this EXR (app/resume.h)
  std::string env_file;                // --env
  std::vector<float> env_color;        // --env-color (3 values) or empty
  float env_scale = 1.0f;              // --env-scale
  std::optional<float> aperture;       // --aperture (else the glTF camera's extras, else 0)
  std::optional<float> focus_distance; // --focus-distance
  // The options given on the command line, by name ("--max-depth"): one the chosen
  // integrator does not read is refused (integrator_ignores).
  std::vector<std::string> given;
};

// The option of `given` that `integrator` does not read, if any: --max-depth and
// --light-samples mean nothing to the debug views and ao, the environment lights only
// the path tracer. Every other render option applies to every integrator.
std::optional<std::string> integrator_ignores(IntegratorKind integrator, const std::vector<std::string>& given);

// Returns the process exit code (130 or 143 after SIGINT or SIGTERM, once the image so far
// is written); messages go to `err`, the summary line to `out`.
// The kd-tree options `--kd-split` selects; throws std::invalid_argument on a bad name.
KdBuildOptions kd_options_from(const std::string& split);

// The ISA `--isa` names, or the best this CPU supports when empty; throws
// std::invalid_argument for an unknown name or one this CPU cannot run.
Isa isa_from(const std::string& name);

// Warns on `err` about what the reader dropped or repaired in `scene`.
void print_load_warnings(const Scene& scene, std::ostream& err);

int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
