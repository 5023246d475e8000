// KHR_draco_mesh_compression: a primitive whose vertex data and indices are one Draco
// bitstream (Google's Draco library, libdraco-dev, decodes it: a compressor's format is
// best read by its own well-kept decoder, not a second implementation).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec4.hpp>

#include "scene/gltf_accessors.h"

namespace tinygltf {
struct Primitive;
}

namespace lancer::gltf {

struct DracoPrimitive {
  std::size_t points = 0;
  std::vector<std::uint32_t> indices;  // three per triangle, each < points
  // The compressed attributes by glTF semantic (POSITION, NORMAL, TEXCOORD_0, ...), four
  // floats per point: integers normalized when the accessor or the Draco attribute says
  // so, missing components 0, a three-component COLOR_n's alpha 1.
  std::map<std::string, std::vector<glm::vec4>> attributes;

  const std::vector<glm::vec4>* find(const std::string& semantic) const {
    const auto it = attributes.find(semantic);
    return it == attributes.end() ? nullptr : &it->second;
  }
};

// The primitive's Draco data decoded, or nothing when it does not use the extension.
// Throws SceneError when the extension is malformed, the bitstream does not decode (the
// decoder's message is passed on), the primitive is not made of triangles, or a decoded
// attribute disagrees with its accessor's element count.
std::optional<DracoPrimitive> decode_draco(const ModelRef& m, const tinygltf::Primitive& prim, const std::string& what);

// The file's JSON with "indices" dropped from every primitive that uses the extension,
// or nothing when none has it. Debian's tinygltf (2.7) refuses an index accessor without
// a bufferView, which is how the extension writes it (the indices are in the Draco data,
// and decode_draco supplies them), so the reader hands tinygltf this text instead.
// `json_text` has passed check_gltf_json.
std::optional<std::string> json_without_draco_indices(std::string_view json_text);

}  // namespace lancer::gltf
