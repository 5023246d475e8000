// glTF 2.0 reader (.gltf with external or data-URI buffers, and .glb) through tinygltf.
#pragma once

#include <filesystem>
#include <optional>
#include <span>

#include "scene/scene.h"

namespace lancer {

// Throws SceneError on anything malformed. May return a scene with no triangles. `scene`
// chooses one of the file's scenes (glTF "scenes"); -1 loads its default scene.
// `frame_time`: the scene as its first animation poses it at that time, in seconds
// (gltf_animation.h; nullopt: at each channel's first keyframe). `instancing`: which meshes
// drawn more than once are stored once (Scene::instancing, gltf_mesh_sharing.h).
// `shutter`: the drawings that move while it is open get motions (gltf_mesh_sharing.h);
// everything else is posed at its opening.
Scene read_gltf(const std::filesystem::path& path, int scene = -1, std::optional<double> frame_time = std::nullopt,
                InstancingMode instancing = InstancingMode::Auto, std::optional<Shutter> shutter = std::nullopt);

// The same for a file's bytes already in memory (the fuzz target uses it). `path` is
// only named in messages, gives the folder external buffers and images resolve
// against, and by its extension says whether the bytes must be a binary glTF.
Scene read_gltf_bytes(std::span<const unsigned char> bytes, const std::filesystem::path& path, int scene = -1,
                      std::optional<double> frame_time = std::nullopt,
                      InstancingMode instancing = InstancingMode::Auto, std::optional<Shutter> shutter = std::nullopt);

}  // namespace lancer
