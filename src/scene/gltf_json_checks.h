// Checks on a glTF document's JSON made before tinygltf sees it. tinygltf silently
// ignores optional properties of the wrong type (an "indices": "3" becomes "no
// indices") and does not look at extensionsRequired; both would give a silently
// wrong scene, so they are refused here with the JSON path of the culprit.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace lancer::gltf {

// The extensions Lancer reads or safely ignores; any other one in extensionsRequired
// is refused by name.
bool extension_supported(std::string_view name);

// Parses `json_text` and throws SceneError(file, ...) on invalid JSON, on a required
// extension Lancer does not support, or on a property of the wrong JSON type among
// those the reader depends on (indices, counts, offsets, factors, ...).
void check_gltf_json(const std::string& file, std::string_view json_text);

// The JSON chunk of a binary glTF (.glb) held in `bytes`. Throws SceneError with a
// telling reason ("truncated", "bad magic", ...) when the container is malformed.
std::string_view glb_json_chunk(const std::string& file, std::span<const unsigned char> bytes);

}  // namespace lancer::gltf
