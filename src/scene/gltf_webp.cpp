#include "scene/gltf_webp.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

constexpr const char* kExtension = "EXT_texture_webp";
constexpr std::string_view kWebpDataUri = "data:image/webp;base64,";

}  // namespace

int webp_texture_source(const ModelRef& m, const tinygltf::Texture& texture, const std::string& what) {
  const auto ext = texture.extensions.find(kExtension);
  if (ext == texture.extensions.end()) return -1;
  const std::string name = what + " " + kExtension;
  const tinygltf::Value& e = ext->second;
  const int source = e.IsObject() && e.Has("source") ? json_index(e.Get("source")) : -1;
  if (source < 0) throw SceneError(m.file, name + " must be an object with a 'source' image index");
  if (std::size_t(source) >= m.model.images.size())
    throw SceneError(m.file, name + ": image index " + std::to_string(source) + " out of range (the file has " +
                                 std::to_string(m.model.images.size()) + " images)");
  return source;
}

std::optional<std::string> json_with_webp_data_uris_relabelled(std::string_view json_text) {
  // A cheap look first: most files hold no WebP data URI.
  if (json_text.find(kWebpDataUri) == std::string_view::npos) return std::nullopt;
  nlohmann::json doc = nlohmann::json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (!doc.is_object() || !doc.contains("images") || !doc["images"].is_array()) return std::nullopt;
  bool changed = false;
  for (nlohmann::json& image : doc["images"]) {
    if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string()) continue;
    const std::string& uri = image["uri"].get_ref<const std::string&>();
    if (uri.rfind(kWebpDataUri, 0) != 0) continue;
    image["uri"] = "data:application/octet-stream;base64," + uri.substr(kWebpDataUri.size());
    changed = true;
  }
  if (!changed) return std::nullopt;
  return doc.dump();
}

}  // namespace lancer::gltf
