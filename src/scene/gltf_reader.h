// glTF 2.0 reader (.gltf with external or data-URI buffers, and .glb) through tinygltf.
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace lancer {

// Throws SceneError on anything malformed. May return a scene with no triangles.
Scene read_gltf(const std::filesystem::path& path);

}  // namespace lancer
