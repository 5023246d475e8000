// glTF materials, textures, samplers and images into Lancer's scene model.
#pragma once

#include "scene/gltf_accessors.h"
#include "scene/scene.h"

namespace lancer::gltf {

// Appends one lancer::Material per glTF material, in file order (so glTF material i
// is scene material i), reading the pbrMetallicRoughness model and the extensions
// KHR_materials_emissive_strength, _ior, _transmission, _specular and _volume (with
// their textures), and KHR_texture_transform on every texture reference. Throws
// SceneError on an unknown alphaMode, a texture index out of range or an extension
// property of the wrong type or out of its range.
void read_materials(const ModelRef& m, Scene& scene);

// Appends the textures (with their samplers; a texture with EXT_texture_webp uses the
// WebP image, gltf_webp.h) and the decoded 8-bit images. Throws
// SceneError when an image cannot be read, is truncated or cannot be decoded, an index
// is out of range, or a sampler has an unknown wrap or filter enum.
void read_textures_and_images(const ModelRef& m, Scene& scene);

}  // namespace lancer::gltf
