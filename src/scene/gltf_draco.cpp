#include "scene/gltf_draco.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <cmath>

#include <glm/common.hpp>

#include "scene/draco_bitstream.h"
#include "scene/scene_error.h"

namespace lancer::gltf {

std::optional<DracoPrimitive> decode_draco(const ModelRef& m, const tinygltf::Primitive& prim, const std::string& what) {
  const auto ext = prim.extensions.find("KHR_draco_mesh_compression");
  if (ext == prim.extensions.end()) return std::nullopt;
  const std::string name = what + " KHR_draco_mesh_compression";
  const tinygltf::Value& e = ext->second;
  if (!e.IsObject() || !e.Has("bufferView") || json_index(e.Get("bufferView")) < 0 || !e.Has("attributes") ||
      !e.Get("attributes").IsObject())
    throw SceneError(m.file, name + " must be an object with a 'bufferView' index and an 'attributes' object");
  // The extension allows TRIANGLES and TRIANGLE_STRIP; either decodes to triangles.
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP)
    throw SceneError(m.file, name + ": only TRIANGLES and TRIANGLE_STRIP primitives can be Draco-compressed (mode " +
                                 std::to_string(prim.mode) + ")");
  const ByteSpan bytes = buffer_view_bytes(m, json_index(e.Get("bufferView")), name);

  draco_io::Mesh mesh;
  std::string error;
  if (!draco_io::decode_mesh(bytes.data, bytes.size, mesh, error))
    throw SceneError(m.file, name + ": Draco data does not decode: " + error);
  DracoPrimitive out;
  out.points = mesh.points;
  out.indices = std::move(mesh.indices);

  const tinygltf::Value& attributes = e.Get("attributes");
  for (const std::string& semantic : attributes.Keys()) {
    const tinygltf::Value& id = attributes.Get(semantic);
    const int unique_id = json_index(id);
    if (unique_id < 0) throw SceneError(m.file, name + " attribute " + semantic + " must be a Draco attribute id");
    const draco_io::Attribute* att = nullptr;
    for (const draco_io::Attribute& a : mesh.attributes)
      if (a.unique_id == std::uint32_t(unique_id)) att = &a;
    if (!att)
      throw SceneError(m.file, name + " attribute " + semantic + ": no Draco attribute has id " + std::to_string(unique_id));
    // The accessor describes the decoded data: its count, and whether integers are normalized.
    const auto accessor = prim.attributes.find(semantic);
    bool normalized = false;
    if (accessor != prim.attributes.end() && accessor->second >= 0 &&
        std::size_t(accessor->second) < m.model.accessors.size()) {
      const tinygltf::Accessor& a = m.model.accessors[std::size_t(accessor->second)];
      if (a.count != out.points)
        throw SceneError(m.file, name + " attribute " + semantic + ": its accessor has " + std::to_string(a.count) +
                                     " elements but the Draco data " + std::to_string(out.points) + " points");
      normalized = a.normalized;
    }
    const float scale = normalized && att->integer && !att->normalized ? att->integer_max : 0.0f;
    std::vector<glm::vec4> values(out.points, glm::vec4(0.0f));
    for (std::size_t p = 0; p < out.points; ++p) {
      glm::vec4& v = values[p];
      v = glm::vec4(att->values[4 * p], att->values[4 * p + 1], att->values[4 * p + 2], att->values[4 * p + 3]);
      if (scale > 0.0f) v = glm::max(v / scale, glm::vec4(-1.0f));
      if (semantic.rfind("COLOR_", 0) == 0 && att->components == 3) v.w = 1.0f;
      if (!std::isfinite(v.x + v.y + v.z + v.w))
        throw SceneError(m.file, name + " attribute " + semantic + " holds a non-finite value");
    }
    out.attributes.emplace(semantic, std::move(values));
  }
  return out;
}

std::optional<std::string> json_without_draco_indices(std::string_view json_text) {
  // A cheap look first: most files never name the extension.
  if (json_text.find("KHR_draco_mesh_compression") == std::string_view::npos) return std::nullopt;
  nlohmann::json doc = nlohmann::json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return std::nullopt;
  bool changed = false;
  for (nlohmann::json& mesh : doc["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (nlohmann::json& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("indices") || !prim.contains("extensions") ||
          !prim["extensions"].is_object() || !prim["extensions"].contains("KHR_draco_mesh_compression"))
        continue;
      prim.erase("indices");
      changed = true;
    }
  }
  if (!changed) return std::nullopt;
  return doc.dump();
}

}  // namespace lancer::gltf
