// `lancer info`: what a scene holds and what the accelerator built over it looks like.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "scene/scene.h"

namespace lancer {

struct InfoOptions {
  std::string scene;
  std::optional<int> gltf_scene;  // --scene
  InstancingMode instancing = InstancingMode::Auto;  // --instancing
  std::string accel = "kdtree";
  std::string kd_split = "sah";
  std::string isa;  // empty: the best this CPU supports
};

int run_info(const InfoOptions& options, std::ostream& out, std::ostream& err);

}  // namespace lancer
