#include "scene/gltf_materials.h"

#include <stb_image.h>
#include <tiny_gltf.h>

#include <climits>
#include <cstring>

#include "scene/scene_error.h"

namespace lancer::gltf {

namespace {

// Images larger than this many pixels are refused before decoding (a corrupt header
// could otherwise ask stb for gigabytes).
constexpr long long kMaxImagePixels = 1ll << 28;

std::string material_name(int index) { return "material " + std::to_string(index); }

TextureRef texture_ref(const ModelRef& m, int texture, int texcoord, double scale, const std::string& what) {
  TextureRef ref;
  if (texture < 0) return ref;  // absent
  if (std::size_t(texture) >= m.model.textures.size())
    throw SceneError(m.file, what + ": texture index " + std::to_string(texture) + " out of range (the file has " +
                                 std::to_string(m.model.textures.size()) + " textures)");
  ref.texture = texture;
  ref.texcoord = texcoord;
  ref.scale = float(scale);
  return ref;
}

// The number ext[key] of a material extension object, or `fallback` when absent.
float extension_number(const ModelRef& m, const tinygltf::Value& ext, const char* key, float fallback,
                       const std::string& what) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsNumber()) throw SceneError(m.file, "wrong JSON type: " + what + "." + key + " must be a number");
  return float(v.GetNumberAsDouble());
}

glm::vec3 extension_vec3(const ModelRef& m, const tinygltf::Value& ext, const char* key, glm::vec3 fallback,
                         const std::string& what) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  bool ok = v.IsArray() && v.ArrayLen() == 3;
  for (int i = 0; ok && i < 3; ++i) ok = v.Get(i).IsNumber();
  if (!ok) throw SceneError(m.file, "wrong JSON type: " + what + "." + key + " must be an array of 3 numbers");
  return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()),
          float(v.Get(2).GetNumberAsDouble())};
}

// The object material.extensions[name], or null when the material does not use it.
const tinygltf::Value* extension_object(const ModelRef& m, const tinygltf::Material& g, const char* name,
                                        const std::string& what) {
  const auto it = g.extensions.find(name);
  if (it == g.extensions.end()) return nullptr;
  if (!it->second.IsObject())
    throw SceneError(m.file, "wrong JSON type: " + what + ".extensions." + name + " must be an object");
  return &it->second;
}

AlphaMode alpha_mode(const ModelRef& m, const std::string& mode, const std::string& what) {
  if (mode == "OPAQUE") return AlphaMode::Opaque;
  if (mode == "MASK") return AlphaMode::Mask;
  if (mode == "BLEND") return AlphaMode::Blend;
  throw SceneError(m.file, what + ": unknown alphaMode '" + mode + "' (expected OPAQUE, MASK or BLEND)");
}

Material convert_material(const ModelRef& m, int index) {
  const tinygltf::Material& g = m.model.materials[std::size_t(index)];
  const std::string what = material_name(index);
  const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
  Material out;
  out.name = g.name;
  if (pbr.baseColorFactor.size() != 4 || g.emissiveFactor.size() != 3)
    throw SceneError(m.file, what + ": baseColorFactor must have 4 numbers and emissiveFactor 3");
  out.base_color =
      glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
  out.base_color_texture =
      texture_ref(m, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1.0, what + " baseColorTexture");
  out.metallic = float(pbr.metallicFactor);
  out.roughness = float(pbr.roughnessFactor);
  out.metallic_roughness_texture =
      texture_ref(m, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1.0,
                  what + " metallicRoughnessTexture");
  out.emissive_factor = glm::vec3(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]);
  out.emissive_texture =
      texture_ref(m, g.emissiveTexture.index, g.emissiveTexture.texCoord, 1.0, what + " emissiveTexture");
  out.normal_texture =
      texture_ref(m, g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.scale, what + " normalTexture");
  out.occlusion_texture = texture_ref(m, g.occlusionTexture.index, g.occlusionTexture.texCoord,
                                      g.occlusionTexture.strength, what + " occlusionTexture");
  out.alpha_mode = alpha_mode(m, g.alphaMode, what);
  out.alpha_cutoff = float(g.alphaCutoff);
  out.double_sided = g.doubleSided;

  const std::string json_path = "materials[" + std::to_string(index) + "]";
  if (const auto* ext = extension_object(m, g, "KHR_materials_emissive_strength", json_path))
    out.emissive_strength =
        extension_number(m, *ext, "emissiveStrength", 1.0f, json_path + ".extensions.KHR_materials_emissive_strength");
  if (const auto* ext = extension_object(m, g, "KHR_materials_ior", json_path))
    out.ior = extension_number(m, *ext, "ior", 1.5f, json_path + ".extensions.KHR_materials_ior");
  if (const auto* ext = extension_object(m, g, "KHR_materials_transmission", json_path))
    out.transmission =
        extension_number(m, *ext, "transmissionFactor", 0.0f, json_path + ".extensions.KHR_materials_transmission");
  if (const auto* ext = extension_object(m, g, "KHR_materials_specular", json_path)) {
    const std::string ext_path = json_path + ".extensions.KHR_materials_specular";
    out.specular = extension_number(m, *ext, "specularFactor", 1.0f, ext_path);
    out.specular_color = extension_vec3(m, *ext, "specularColorFactor", glm::vec3(1.0f), ext_path);
  }
  return out;
}

// The encoded bytes of image `index`: from its bufferView (bounds-checked here, as
// tinygltf hands the loader callback an unchecked pointer) or as loaded from its URI.
ByteSpan encoded_image(const ModelRef& m, int index, const std::string& what) {
  const tinygltf::Image& img = m.model.images[std::size_t(index)];
  if (img.bufferView >= 0) return buffer_view_bytes(m, img.bufferView, what);
  if (img.image.empty())
    throw SceneError(m.file, what + " ('" + img.uri + "') could not be read (missing file or empty data)");
  return {img.image.data(), img.image.size()};
}

Image decode_image(const ModelRef& m, int index) {
  const tinygltf::Image& src = m.model.images[std::size_t(index)];
  const std::string what = "image " + std::to_string(index);
  const ByteSpan bytes = encoded_image(m, index, what);
  if (bytes.size > std::size_t(INT_MAX)) throw SceneError(m.file, what + " is too large to decode (over 2 GiB)");
  const int length = int(bytes.size);
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data, length, &width, &height, &channels))
    throw SceneError(m.file, what + " cannot be decoded: " + std::string(stbi_failure_reason()));
  if (width <= 0 || height <= 0 || (long long)width * height > kMaxImagePixels)
    throw SceneError(m.file, what + " has unsupported size " + std::to_string(width) + "x" + std::to_string(height));
  stbi_uc* pixels = stbi_load_from_memory(bytes.data, length, &width, &height, &channels, 0);
  if (!pixels) throw SceneError(m.file, what + " cannot be decoded: " + std::string(stbi_failure_reason()));
  Image out;
  out.name = !src.uri.empty() ? src.uri : !src.name.empty() ? src.name : what + " (embedded)";
  out.width = width;
  out.height = height;
  out.channels = channels;
  out.pixels.assign(pixels, pixels + std::size_t(width) * std::size_t(height) * std::size_t(channels));
  stbi_image_free(pixels);
  return out;
}

}  // namespace

void read_materials(const ModelRef& m, Scene& scene) {
  for (std::size_t i = 0; i < m.model.materials.size(); ++i) scene.materials.push_back(convert_material(m, int(i)));
}

void read_textures_and_images(const ModelRef& m, Scene& scene) {
  for (std::size_t i = 0; i < m.model.images.size(); ++i) scene.images.push_back(decode_image(m, int(i)));
  for (std::size_t i = 0; i < m.model.textures.size(); ++i) {
    const tinygltf::Texture& t = m.model.textures[i];
    const std::string what = "texture " + std::to_string(i);
    Texture out;
    if (t.source >= int(m.model.images.size()))
      throw SceneError(m.file, what + ": image index " + std::to_string(t.source) + " out of range (the file has " +
                                   std::to_string(m.model.images.size()) + " images)");
    out.image = t.source < 0 ? -1 : t.source;
    if (t.sampler >= int(m.model.samplers.size()))
      throw SceneError(m.file, what + ": sampler index " + std::to_string(t.sampler) + " out of range (the file has " +
                                   std::to_string(m.model.samplers.size()) + " samplers)");
    if (t.sampler >= 0) {
      const tinygltf::Sampler& s = m.model.samplers[std::size_t(t.sampler)];
      out.wrap_s = s.wrapS;
      out.wrap_t = s.wrapT;
      out.mag_filter = s.magFilter;
      out.min_filter = s.minFilter;
    }
    scene.textures.push_back(out);
  }
}

}  // namespace lancer::gltf
