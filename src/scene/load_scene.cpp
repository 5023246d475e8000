#include "scene/load_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include "scene/gltf_reader.h"
#include "scene/obj_reader.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"
#include "simd/release_free_memory.h"

namespace lancer {

Scene load_scene(const std::filesystem::path& path, std::optional<int> gltf_scene, std::optional<double> frame_time,
                 InstancingMode instancing, std::optional<Shutter> shutter) {
  const std::string file = path.string();
  if (frame_time && !std::isfinite(*frame_time))
    throw SceneError(file, "--frame-time " + std::to_string(*frame_time) + ": not a time on the timeline");
  if (shutter && !(std::isfinite(shutter->open) && std::isfinite(shutter->close) && shutter->open <= shutter->close))
    throw SceneError(file, "--shutter " + std::to_string(shutter->open) + "," + std::to_string(shutter->close) +
                               ": not an interval of the timeline (OPEN <= CLOSE, both finite)");
  if (shutter && frame_time) throw SceneError(file, "--shutter and --frame-time: choose one (the shutter opens at OPEN)");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw SceneError(file, "no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw SceneError(file, "not a regular file");

  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  SceneWarningLog warnings;
  Scene scene;
  if (ext == ".gltf" || ext == ".glb") {
    scene = read_gltf(path, gltf_scene.value_or(-1), frame_time, instancing, shutter);
  } else if (ext == ".obj") {
    if (gltf_scene) throw SceneError(file, "--scene: an OBJ file has no scenes to choose from");
    if (frame_time) throw SceneError(file, "--frame-time: an OBJ file has no animation");
    if (shutter) throw SceneError(file, "--shutter: an OBJ file has no animation to blur");
    scene = read_obj(path);
  } else {
    throw SceneError(file, "unknown scene format '" + ext + "' (expected .gltf, .glb or .obj)");
  }
  if (scene.triangle_count() == 0) throw SceneError(file, "the scene has no triangles");
  scene.warnings = warnings.take();
  release_free_memory();  // the reader's freed copies (file, decoded accessors), before the build
  return scene;
}

}  // namespace lancer
