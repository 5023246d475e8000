// Loads a scene file, choosing the reader by extension (.gltf, .glb, .obj).
#pragma once

#include <filesystem>
#include <optional>

#include "scene/scene.h"

namespace lancer {

// Throws SceneError naming the file and the problem. A scene with no triangles is an error.
// `gltf_scene` (--scene) chooses one of a glTF file's scenes; an OBJ file has none to choose.
// `frame_time` (--frame-time, seconds, finite) poses a glTF file's animation at that time;
// an OBJ file has no animation. `instancing` (--instancing) says which of a glTF file's
// meshes drawn more than once are stored once and drawn through instances; an OBJ file
// draws each of its triangles once. `shutter` (--shutter) makes the drawings that move while
// it is open move (Scene::instancing's motions); it excludes `frame_time`, and an OBJ file
// has no animation.
Scene load_scene(const std::filesystem::path& path, std::optional<int> gltf_scene = std::nullopt,
                 std::optional<double> frame_time = std::nullopt, InstancingMode instancing = InstancingMode::Auto,
                 std::optional<Shutter> shutter = std::nullopt);

}  // namespace lancer
