// EXT_meshopt_compression: bufferViews whose bytes are stored compressed elsewhere, decoded
// by meshoptimizer (libmeshoptimizer-dev), the codec author's own library, into memory that
// then stands in for the bufferView's data: every accessor reader works unchanged.
//
// Two steps around tinygltf. Before it parses: the extension objects are read from the
// file's JSON (tinygltf keeps extension integers as int, which would wrap a large count
// silently), and placeholder buffers are replaced. A placeholder is the uncompressed
// "fallback" buffer the spec lets a file leave without data ({"byteLength": N}, no uri):
// tinygltf 2.7 refuses a .gltf buffer without uri, and in a .glb takes any buffer without
// uri for the BIN chunk (refusing it when byteLength exceeds the chunk). After it parses:
// each compressed view is decoded and pointed at a buffer of its own.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tinygltf {
class Model;
}

namespace lancer::gltf {

// The most decoded bytes a file's compressed bufferViews may add up to: more than a GLB
// (32-bit lengths) can hold uncompressed, and a bound on what a small hostile file can
// make the reader allocate (one compressed range may back any number of views).
inline constexpr std::size_t kMaxMeshoptDecodedBytes = std::size_t(1) << 32;

enum class MeshoptMode { Attributes, Triangles, Indices };
enum class MeshoptFilter { None, Octahedral, Quaternion, Exponential };

// One bufferView's extension object, checked against the spec's rules on its own
// ("For the extension object to be valid"); the buffers are checked when decoding.
struct MeshoptView {
  int view = -1;    // the bufferView
  int buffer = -1;  // the buffer holding the compressed bytes
  std::size_t byte_offset = 0, byte_length = 0, byte_stride = 0, count = 0;
  MeshoptMode mode = MeshoptMode::Attributes;
  MeshoptFilter filter = MeshoptFilter::None;
};

struct MeshoptPlan {
  std::vector<MeshoptView> views;
  // The JSON with each placeholder buffer replaced by a 3-byte data URI, or nothing when
  // the file has none. A buffer is a placeholder when no view but compressed ones refers to
  // it, no extension object takes compressed bytes from it, and it is marked
  // {"fallback": true} or has no uri and a compressed view refers to it (in a .glb that may
  // be buffer 0, the BIN chunk: its bytes then serve no one).
  std::optional<std::string> json;
};

// Reads the extension objects of `json_text`, which has passed check_gltf_json. Throws
// SceneError naming the bufferView when one is malformed or breaks the spec's rules.
MeshoptPlan plan_meshopt(const std::string& file, std::string_view json_text);

// Decodes every view of `views` into a new buffer of `model` and points the bufferView at
// it (byteOffset 0). Throws SceneError naming `file`, the bufferView and the extension
// when the compressed bytes lie outside their buffer, cannot hold `count` elements, would
// exceed kMaxMeshoptDecodedBytes, or do not decode. Nothing is allocated before the sizes
// are checked.
void decode_meshopt(const std::vector<MeshoptView>& views, tinygltf::Model& model, const std::string& file);

}  // namespace lancer::gltf
