#include "scene/gltf_texture_refs.h"

#include <tiny_gltf.h>

#include <cmath>

#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer::gltf {

namespace {

constexpr const char* kTransform = "KHR_texture_transform";

glm::vec2 vec2_property(const ModelRef& m, const tinygltf::Value& obj, const char* key, glm::vec2 fallback,
                        const std::string& what) {
  if (!obj.Has(key)) return fallback;
  const tinygltf::Value& v = obj.Get(key);
  if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
    throw SceneError(m.file, "wrong JSON type: " + what + "." + key + " must be an array of 2 numbers");
  return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble())};
}

// A non-negative integer property, or `fallback` when absent.
int index_property(const ModelRef& m, const tinygltf::Value& obj, const char* key, int fallback,
                   const std::string& what) {
  if (!obj.Has(key)) return fallback;
  const tinygltf::Value& v = obj.Get(key);
  if (!v.IsInt() || v.GetNumberAsInt() < 0)
    throw SceneError(m.file, "wrong JSON type: " + what + "." + key + " must be a non-negative integer");
  return v.GetNumberAsInt();
}

// Applies the KHR_texture_transform object `t` to `ref`: its matrix and, when given,
// its texCoord, which overrides the textureInfo's.
void apply_transform(const ModelRef& m, const tinygltf::Value& t, TextureRef& ref, const std::string& what) {
  const std::string path = what + ".extensions." + kTransform;
  if (!t.IsObject()) throw SceneError(m.file, "wrong JSON type: " + path + " must be an object");
  const glm::vec2 offset = vec2_property(m, t, "offset", glm::vec2(0.0f), path);
  const glm::vec2 scale = vec2_property(m, t, "scale", glm::vec2(1.0f), path);
  float rotation = 0.0f;
  if (t.Has("rotation")) {
    if (!t.Get("rotation").IsNumber())
      throw SceneError(m.file, "wrong JSON type: " + path + ".rotation must be a number");
    rotation = float(t.Get("rotation").GetNumberAsDouble());
  }
  ref.transform = texture_transform_matrix(offset, rotation, scale);
  ref.texcoord = index_property(m, t, "texCoord", ref.texcoord, path);
}

}  // namespace

glm::mat3 texture_transform_matrix(glm::vec2 offset, float rotation, glm::vec2 scale) {
  // glm, like GLSL, takes matrices column by column; these are the extension's own
  // GLSL matrices, written the same way.
  const float c = std::cos(rotation), s = std::sin(rotation);
  const glm::mat3 translation(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::mat3 rotate(c, -s, 0, s, c, 0, 0, 0, 1);
  const glm::mat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return translation * rotate * scaling;
}

TextureRef texture_ref(const ModelRef& m, int texture, int texcoord, double scale, const tinygltf::Value* transform,
                       const std::string& what) {
  TextureRef ref;
  if (texture < 0) return ref;  // absent
  if (std::size_t(texture) >= m.model.textures.size())
    throw SceneError(m.file, what + ": texture index " + std::to_string(texture) + " out of range (the file has " +
                                 std::to_string(m.model.textures.size()) + " textures)");
  if (texcoord < 0) throw SceneError(m.file, what + ": texCoord must not be negative");
  ref.texture = texture;
  ref.texcoord = texcoord;
  ref.scale = float(scale);
  if (transform) apply_transform(m, *transform, ref, what);
  if (ref.texcoord > 1) {
    print_scene_warnings(m.file, what + " uses TEXCOORD_" + std::to_string(ref.texcoord) +
                                     "; only TEXCOORD_0 and TEXCOORD_1 are read, so it uses TEXCOORD_0");
    ref.texcoord = 0;
  }
  return ref;
}

TextureRef extension_texture_ref(const ModelRef& m, const tinygltf::Value& ext, const char* key,
                                 const std::string& what) {
  if (!ext.Has(key)) return {};
  const std::string path = what + "." + key;
  const tinygltf::Value& info = ext.Get(key);
  if (!info.IsObject()) throw SceneError(m.file, "wrong JSON type: " + path + " must be an object");
  if (!info.Has("index")) throw SceneError(m.file, "missing property: " + path + ".index");
  const int texture = index_property(m, info, "index", -1, path);
  const int texcoord = index_property(m, info, "texCoord", 0, path);
  const tinygltf::Value* transform = nullptr;
  if (info.Has("extensions")) {
    const tinygltf::Value& extensions = info.Get("extensions");
    if (!extensions.IsObject()) throw SceneError(m.file, "wrong JSON type: " + path + ".extensions must be an object");
    if (extensions.Has(kTransform)) transform = &extensions.Get(kTransform);
  }
  return texture_ref(m, texture, texcoord, 1.0, transform, path);
}

}  // namespace lancer::gltf
