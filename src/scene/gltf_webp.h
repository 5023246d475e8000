// EXT_texture_webp: a texture whose extension names a WebP image uses it (decode_image
// reads WebP with libwebp). When the texture also has a plain `source` (a PNG or JPEG
// fallback for viewers without WebP), the WebP image is used: the file's author marked it
// the better choice. The fallback image is still decoded, as every image of a file is,
// and a WebP that does not decode is an error, not a silent switch to the fallback: the
// file is damaged, and the render would not show what its author chose.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "scene/gltf_accessors.h"

namespace tinygltf {
struct Texture;
}

namespace lancer::gltf {

// The image of texture.extensions.EXT_texture_webp.source, or -1 when the texture does
// not use the extension. Throws SceneError naming `what` when the extension is malformed
// or names an image the file lacks.
int webp_texture_source(const ModelRef& m, const tinygltf::Texture& texture, const std::string& what);

// The file's JSON with each image data URI of type image/webp ("data:image/webp;base64,")
// relabelled application/octet-stream, or nothing when it has none. tinygltf 2.7 only
// knows a few media types in data URIs and takes any other for a file name; the bytes are
// the same, and decode_image recognises WebP by its header. `json_text` has passed
// check_gltf_json.
std::optional<std::string> json_with_webp_data_uris_relabelled(std::string_view json_text);

}  // namespace lancer::gltf
