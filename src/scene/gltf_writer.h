// Binary glTF 2.0 (.glb) writer through tinygltf, for generated scenes (`lancer gen`).
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace lancer {

// Writes `scene` as one .glb file with the buffer embedded:
//  - triangles: one mesh, one primitive per run of consecutive triangles that share a
//    material and whether they carry normals, in scene order; corners with identical
//    position (and normal) bits are welded into indexed vertices (uint32 indices);
//    POSITION always, NORMAL only for triangles that have normals (kHasNormals);
//  - every material, in order (metallic-roughness factors, emissive factor, alpha
//    mode, double-sidedness, and the emissive_strength, ior, transmission and specular
//    extensions when they differ from their defaults);
//  - each camera as a perspective camera on a node whose matrix is camera_to_world;
//  - each light as a KHR_lights_punctual light on a node at its position, its -z
//    axis along the light's direction.
// Reading the file back with read_gltf gives the same triangles (bit-identical
// positions, same order), materials, cameras and lights. Texture coordinates and
// tangents are not written, and a material that uses a texture is refused.
//
// The file appears atomically: the bytes go to "<path>.tmp", are flushed to disk, and
// the temporary is renamed over `path`. Throws SceneError naming `path` on any failure
// (missing directory, I/O error, a scene with no triangles, a file over the 4 GiB a
// GLB header can describe).
void write_glb(const Scene& scene, const std::filesystem::path& path);

}  // namespace lancer
