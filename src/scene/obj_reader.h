// Wavefront OBJ + MTL reader through tinyobjloader. Polygons are fan-triangulated in
// file order, so a triangle's source id is its position among the file's triangles.
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace lancer {

// Throws SceneError on anything malformed. May return a scene with no triangles.
Scene read_obj(const std::filesystem::path& path);

}  // namespace lancer
