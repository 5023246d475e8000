// `lancer render`: load a scene, build the accelerator, render, write the images.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "render/render_settings.h"

namespace lancer {

struct RenderOptions {
  std::string scene;
  std::vector<std::string> outputs;  // by extension: .exr, .png
  RenderSettings settings;
  bool height_given = false;
  std::string accel = "brute";
  std::optional<int> camera;         // glTF camera index
  std::optional<glm::vec3> eye, look_at, up;
  std::optional<float> fov_degrees;  // vertical
  bool progress = true;
};

// Returns the process exit code; messages go to `err`, the summary line to `out`.
int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
