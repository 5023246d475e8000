// glTF textureInfo objects into TextureRef: the texture index, the texcoord set, the
// normal scale / occlusion strength, and KHR_texture_transform.
#pragma once

#include <string>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include "scene/gltf_accessors.h"
#include "scene/scene.h"

namespace tinygltf {
class Value;
}

namespace lancer::gltf {

// The extension's matrix, translation(offset) * rotation * scale, applied to (u, v, 1)
// (KHR_texture_transform, "Overview"). `rotation` is in radians, counter-clockwise in
// UV space: u' = cos r u + sin r v, v' = -sin r u + cos r v before the offset.
glm::mat3 texture_transform_matrix(glm::vec2 offset, float rotation, glm::vec2 scale);

// A core textureInfo: texture `texture` (-1: absent), set `texcoord`, normal scale or
// occlusion strength `scale`; `transform` is its extensions.KHR_texture_transform
// value, or null. Throws SceneError when the texture index is out of range or the
// transform is malformed. Only TEXCOORD_0 and _1 are read: a higher set is reported on
// stderr and TEXCOORD_0 used instead.
TextureRef texture_ref(const ModelRef& m, int texture, int texcoord, double scale, const tinygltf::Value* transform,
                       const std::string& what);

// The textureInfo ext[key] inside a material extension (transmissionTexture,
// specularTexture, ...), which tinygltf leaves as plain JSON. Absent: an empty ref.
TextureRef extension_texture_ref(const ModelRef& m, const tinygltf::Value& ext, const char* key,
                                 const std::string& what);

}  // namespace lancer::gltf
