// Loads a scene file, choosing the reader by extension (.gltf, .glb, .obj).
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace lancer {

// Throws SceneError naming the file and the problem. A scene with no triangles is an error.
Scene load_scene(const std::filesystem::path& path);

}  // namespace lancer
