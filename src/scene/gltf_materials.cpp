#include "scene/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include <tiny_gltf.h>

#include "scene/gltf_texture_refs.h"
#include "scene/gltf_webp.h"
#include "scene/image_decode.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer::gltf {

namespace {

std::string material_name(int index) { return "material " + std::to_string(index); }

// The KHR_texture_transform value in a core textureInfo's extensions, or null.
const tinygltf::Value* texture_transform(const tinygltf::ExtensionMap& extensions) {
  const auto it = extensions.find("KHR_texture_transform");
  return it == extensions.end() ? nullptr : &it->second;
}

template <typename Info>
TextureRef core_texture_ref(const ModelRef& m, const Info& info, double scale, const std::string& what) {
  return texture_ref(m, info.index, info.texCoord, scale, texture_transform(info.extensions), what);
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

// KHR_materials_volume. The extension requires thicknessFactor >= 0 and
// attenuationDistance > 0; its default distance, infinity, means no attenuation.
void read_volume(const ModelRef& m, const tinygltf::Value& ext, const std::string& path, Material& out) {
  out.thickness = extension_number(m, ext, "thicknessFactor", 0.0f, path);
  if (!(out.thickness >= 0.0f)) throw SceneError(m.file, path + ".thicknessFactor must not be negative");
  out.thickness_texture = extension_texture_ref(m, ext, "thicknessTexture", path);
  out.attenuation_distance = extension_number(m, ext, "attenuationDistance", out.attenuation_distance, path);
  if (!(out.attenuation_distance > 0.0f)) throw SceneError(m.file, path + ".attenuationDistance must be positive");
  out.attenuation_color = extension_vec3(m, ext, "attenuationColor", glm::vec3(1.0f), path);
}

// JSON allows any number, but a factor beyond float's range (1e39, say) becomes an
// infinity here and NaN in the image: refuse it, naming the material. Only the
// attenuation distance may be infinite (its default: no attenuation).
void require_finite_factors(const ModelRef& m, const Material& out, const std::string& what) {
  const glm::vec3 emission = out.emission();
  for (const float x : {out.base_color.r, out.base_color.g, out.base_color.b, out.base_color.a, out.metallic,
                        out.roughness, emission.r, emission.g, emission.b, out.alpha_cutoff, out.ior,
                        out.transmission, out.specular, out.specular_color.r, out.specular_color.g,
                        out.specular_color.b, out.thickness, out.attenuation_color.r, out.attenuation_color.g,
                        out.attenuation_color.b, out.clearcoat, out.clearcoat_roughness, out.sheen_color.r,
                        out.sheen_color.g, out.sheen_color.b, out.sheen_roughness})
    if (!std::isfinite(x)) throw SceneError(m.file, what + ": a factor is beyond the range of float");
  for (const TextureRef* t : {&out.base_color_texture, &out.metallic_roughness_texture, &out.emissive_texture,
                              &out.normal_texture, &out.occlusion_texture, &out.transmission_texture,
                              &out.specular_texture, &out.specular_color_texture, &out.thickness_texture,
                              &out.clearcoat_texture, &out.clearcoat_roughness_texture, &out.clearcoat_normal_texture,
                              &out.sheen_color_texture, &out.sheen_roughness_texture}) {
    bool finite = std::isfinite(t->scale);
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) finite = finite && std::isfinite(t->transform[col][row]);
    if (!finite)
      throw SceneError(m.file, what + ": a texture's scale or KHR_texture_transform is beyond the range of float");
  }
}

// KHR_materials_clearcoat. The clearcoat normal texture keeps its normalTextureInfo scale.
void read_clearcoat(const ModelRef& m, const tinygltf::Value& ext, const std::string& path, Material& out) {
  out.clearcoat = extension_number(m, ext, "clearcoatFactor", 0.0f, path);
  out.clearcoat_texture = extension_texture_ref(m, ext, "clearcoatTexture", path);
  out.clearcoat_roughness = extension_number(m, ext, "clearcoatRoughnessFactor", 0.0f, path);
  out.clearcoat_roughness_texture = extension_texture_ref(m, ext, "clearcoatRoughnessTexture", path);
  out.clearcoat_normal_texture = extension_texture_ref(m, ext, "clearcoatNormalTexture", path);
  if (out.clearcoat_normal_texture.present())
    out.clearcoat_normal_texture.scale =
        extension_number(m, ext.Get("clearcoatNormalTexture"), "scale", 1.0f, path + ".clearcoatNormalTexture");
}

// KHR_materials_sheen: colour factor linear, colour texture sRGB RGB, roughness texture A.
void read_sheen(const ModelRef& m, const tinygltf::Value& ext, const std::string& path, Material& out) {
  out.sheen_color = extension_vec3(m, ext, "sheenColorFactor", glm::vec3(0.0f), path);
  out.sheen_color_texture = extension_texture_ref(m, ext, "sheenColorTexture", path);
  out.sheen_roughness = extension_number(m, ext, "sheenRoughnessFactor", 0.0f, path);
  out.sheen_roughness_texture = extension_texture_ref(m, ext, "sheenRoughnessTexture", path);
}

glm::vec4 extension_vec4(const ModelRef& m, const tinygltf::Value& ext, const char* key, glm::vec4 fallback,
                         const std::string& what) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  bool ok = v.IsArray() && v.ArrayLen() == 4;
  for (int i = 0; ok && i < 4; ++i) ok = v.Get(i).IsNumber();
  if (!ok) throw SceneError(m.file, "wrong JSON type: " + what + "." + key + " must be an array of 4 numbers");
  return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()),
          float(v.Get(2).GetNumberAsDouble()), float(v.Get(3).GetNumberAsDouble())};
}

// The glossiness in specularGlossinessTexture's alpha as a metallic-roughness texture of its
// own: G = 1 - glossinessFactor * A (roughness), B = 0 (metallic), R unused, with the
// texture's sampler. An image without alpha has glossiness 1 everywhere. Returns the new
// texture's index, or -1 when the texture has no image.
int roughness_texture_from_glossiness(Scene& scene, int texture, float glossiness) {
  const Texture source = scene.textures.at(std::size_t(texture));
  if (source.image < 0) return -1;
  const Image& from = scene.images.at(std::size_t(source.image));
  Image to;
  to.name = from.name + " (roughness from its glossiness)";
  to.width = from.width;
  to.height = from.height;
  to.channels = 3;
  const std::size_t texels = std::size_t(from.width) * std::size_t(from.height);
  to.pixels.assign(texels * 3, 0);
  const int c = from.channels;
  for (std::size_t i = 0; i < texels; ++i) {
    const float a = c == 2 || c == 4 ? from.pixels[i * std::size_t(c) + std::size_t(c - 1)] / 255.0f : 1.0f;
    const float roughness = std::clamp(1.0f - glossiness * a, 0.0f, 1.0f);
    to.pixels[i * 3 + 1] = static_cast<std::uint8_t>(std::lround(roughness * 255.0f));
  }
  scene.images.push_back(std::move(to));
  Texture derived = source;
  derived.image = int(scene.images.size() - 1);
  scene.textures.push_back(derived);
  return int(scene.textures.size() - 1);
}

// KHR_materials_pbrSpecularGlossiness (archived), converted to metallic-roughness at load:
//   baseColor = diffuseFactor (diffuseTexture: baseColorTexture), metallic = 0,
//   roughness = 1 - glossinessFactor,
//   KHR_materials_specular: specularColorFactor = specularFactor, specularFactor 1, with
//   KHR_materials_ior's ior = 0 (dielectric_f0 = 1), so that f0 = specularFactor exactly
//   (KHR_materials_ior, "ior = 0 ... for specular-glossiness conversions"); then the base's
//   1 - specular * max(fr) is the extension's diffuse (1 - max(specular)) at normal incidence.
//   specularGlossinessTexture: its RGB (sRGB) becomes specularColorTexture, and its A
//   (glossiness) a derived metallic-roughness texture (roughness = 1 - glossinessFactor * A
//   is not a factor times a channel of the file's texture, so the channel is computed at
//   load, once per texture and glossinessFactor).
// The roughness textures derived so far, by (texture, glossinessFactor), and the bytes they
// may still take: one RGB copy of each of the file's images in all, so that a file cannot
// multiply its memory by giving many materials one big texture with different factors.
struct DerivedTextures {
  static std::size_t rgb_bytes(const Image& image) { return std::size_t(image.width) * std::size_t(image.height) * 3; }

  std::map<std::pair<int, float>, int> index;
  std::size_t bytes_left = 0;
};

void read_specular_glossiness(const ModelRef& m, const tinygltf::Value& ext, const std::string& path, Scene& scene,
                              DerivedTextures& derived, Material& out) {
  out.base_color = extension_vec4(m, ext, "diffuseFactor", glm::vec4(1.0f), path);
  out.base_color_texture = extension_texture_ref(m, ext, "diffuseTexture", path);
  out.metallic = 0.0f;
  out.metallic_roughness_texture = {};
  const float glossiness = extension_number(m, ext, "glossinessFactor", 1.0f, path);
  out.roughness = 1.0f - glossiness;
  out.specular = 1.0f;
  out.specular_color = extension_vec3(m, ext, "specularFactor", glm::vec3(1.0f), path);
  out.ior = 0.0f;
  out.specular_color_texture = extension_texture_ref(m, ext, "specularGlossinessTexture", path);
  if (out.specular_color_texture.present()) {
    const std::pair<int, float> key{out.specular_color_texture.texture, glossiness};
    auto it = derived.index.find(key);
    if (it == derived.index.end()) {
      const int image = scene.textures.at(std::size_t(key.first)).image;
      const std::size_t bytes = image < 0 ? 0 : DerivedTextures::rgb_bytes(scene.images[std::size_t(image)]);
      if (bytes > derived.bytes_left) {
        print_scene_warnings(m.file, path +
                                         ".specularGlossinessTexture: its glossiness (alpha) is not converted (the "
                                         "roughness textures derived from the file's images would outgrow one copy "
                                         "of them); roughness = 1 - glossinessFactor here");
        return;
      }
      derived.bytes_left -= bytes;
      it = derived.index.emplace(key, roughness_texture_from_glossiness(scene, key.first, glossiness)).first;
    }
    if (it->second >= 0) {
      out.metallic_roughness_texture = out.specular_color_texture;
      out.metallic_roughness_texture.texture = it->second;
      out.roughness = 1.0f;  // the texture's G holds the whole roughness
    }
  }
}

AlphaMode alpha_mode(const ModelRef& m, const std::string& mode, const std::string& what) {
  if (mode == "OPAQUE") return AlphaMode::Opaque;
  if (mode == "MASK") return AlphaMode::Mask;
  if (mode == "BLEND") return AlphaMode::Blend;
  throw SceneError(m.file, what + ": unknown alphaMode '" + mode + "' (expected OPAQUE, MASK or BLEND)");
}

Material convert_material(const ModelRef& m, int index, Scene& scene, DerivedTextures& derived) {
  const tinygltf::Material& g = m.model.materials[std::size_t(index)];
  const std::string what = material_name(index);
  const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
  Material out;
  out.name = g.name;
  if (pbr.baseColorFactor.size() != 4 || g.emissiveFactor.size() != 3)
    throw SceneError(m.file, what + ": baseColorFactor must have 4 numbers and emissiveFactor 3");
  out.base_color =
      glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
  out.base_color_texture = core_texture_ref(m, pbr.baseColorTexture, 1.0, what + " baseColorTexture");
  out.metallic = float(pbr.metallicFactor);
  out.roughness = float(pbr.roughnessFactor);
  out.metallic_roughness_texture =
      core_texture_ref(m, pbr.metallicRoughnessTexture, 1.0, what + " metallicRoughnessTexture");
  out.emissive_factor = glm::vec3(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]);
  out.emissive_texture = core_texture_ref(m, g.emissiveTexture, 1.0, what + " emissiveTexture");
  out.normal_texture = core_texture_ref(m, g.normalTexture, g.normalTexture.scale, what + " normalTexture");
  out.occlusion_texture =
      core_texture_ref(m, g.occlusionTexture, g.occlusionTexture.strength, what + " occlusionTexture");
  out.alpha_mode = alpha_mode(m, g.alphaMode, what);
  out.alpha_cutoff = float(g.alphaCutoff);
  out.double_sided = g.doubleSided;

  const std::string json_path = "materials[" + std::to_string(index) + "]";
  if (const auto* ext = extension_object(m, g, "KHR_materials_emissive_strength", json_path))
    out.emissive_strength =
        extension_number(m, *ext, "emissiveStrength", 1.0f, json_path + ".extensions.KHR_materials_emissive_strength");
  if (const auto* ext = extension_object(m, g, "KHR_materials_ior", json_path))
    out.ior = extension_number(m, *ext, "ior", 1.5f, json_path + ".extensions.KHR_materials_ior");
  if (const auto* ext = extension_object(m, g, "KHR_materials_transmission", json_path)) {
    const std::string ext_path = json_path + ".extensions.KHR_materials_transmission";
    out.transmission = extension_number(m, *ext, "transmissionFactor", 0.0f, ext_path);
    out.transmission_texture = extension_texture_ref(m, *ext, "transmissionTexture", ext_path);
  }
  if (const auto* ext = extension_object(m, g, "KHR_materials_specular", json_path)) {
    const std::string ext_path = json_path + ".extensions.KHR_materials_specular";
    out.specular = extension_number(m, *ext, "specularFactor", 1.0f, ext_path);
    out.specular_color = extension_vec3(m, *ext, "specularColorFactor", glm::vec3(1.0f), ext_path);
    out.specular_texture = extension_texture_ref(m, *ext, "specularTexture", ext_path);
    out.specular_color_texture = extension_texture_ref(m, *ext, "specularColorTexture", ext_path);
  }
  if (const auto* ext = extension_object(m, g, "KHR_materials_volume", json_path))
    read_volume(m, *ext, json_path + ".extensions.KHR_materials_volume", out);
  if (const auto* ext = extension_object(m, g, "KHR_materials_clearcoat", json_path))
    read_clearcoat(m, *ext, json_path + ".extensions.KHR_materials_clearcoat", out);
  if (const auto* ext = extension_object(m, g, "KHR_materials_sheen", json_path))
    read_sheen(m, *ext, json_path + ".extensions.KHR_materials_sheen", out);
  if (extension_object(m, g, "KHR_materials_unlit", json_path)) out.unlit = true;
  if (const auto* ext = extension_object(m, g, "KHR_materials_pbrSpecularGlossiness", json_path))
    read_specular_glossiness(m, *ext, json_path + ".extensions.KHR_materials_pbrSpecularGlossiness", scene,
                             derived, out);
  require_finite_factors(m, out, what);
  return out;
}

// The encoded bytes of image `index`: from its bufferView (bounds-checked here, as
// tinygltf hands the loader callback an unchecked pointer) or as loaded from its URI.
ByteSpan encoded_image(const ModelRef& m, int index, const std::string& what) {
  const tinygltf::Image& img = m.model.images[std::size_t(index)];
  if (img.bufferView >= 0) return buffer_view_bytes(m, img.bufferView, what);
  if (img.image.empty()) throw SceneError(m.file, what + " could not be read (missing file or empty data)");
  return {img.image.data(), img.image.size()};
}

Image decode_gltf_image(const ModelRef& m, int index) {
  const tinygltf::Image& src = m.model.images[std::size_t(index)];
  const std::string number = "image " + std::to_string(index);
  // Messages name the image by its index and, when it has one, its file or name (cut
  // short: a data URI of a type tinygltf does not know is kept as the "file name").
  const std::string& label = !src.uri.empty() ? src.uri : src.name;
  const std::string shown = label.size() > 80 ? label.substr(0, 77) + "..." : label;
  const std::string what = label.empty() ? number : number + " ('" + shown + "')";
  const ByteSpan bytes = encoded_image(m, index, what);
  std::string name = !label.empty() ? label : number + " (embedded)";
  return decode_image({bytes.data, bytes.size}, std::move(name), m.file, what);
}

bool wrap_mode(int v) { return v == 10497 || v == 33071 || v == 33648; }
bool mag_filter(int v) { return v == -1 || v == 9728 || v == 9729; }
bool min_filter(int v) { return mag_filter(v) || (v >= 9984 && v <= 9987); }

// The sampler enums the texture lookup understands (glTF 2.0 spec, "Samplers"); -1 is
// tinygltf's "not given" for the filters.
void check_sampler(const ModelRef& m, const tinygltf::Sampler& s, int index) {
  const std::string what = "sampler " + std::to_string(index);
  auto fail = [&](const char* key, int value, const char* allowed) {
    throw SceneError(m.file, what + ": " + key + " " + std::to_string(value) + " is not one of " + allowed);
  };
  if (!wrap_mode(s.wrapS)) fail("wrapS", s.wrapS, "10497, 33071, 33648");
  if (!wrap_mode(s.wrapT)) fail("wrapT", s.wrapT, "10497, 33071, 33648");
  if (!mag_filter(s.magFilter)) fail("magFilter", s.magFilter, "9728, 9729");
  if (!min_filter(s.minFilter)) fail("minFilter", s.minFilter, "9728, 9729, 9984-9987");
}

}  // namespace

void read_materials(const ModelRef& m, Scene& scene) {
  DerivedTextures derived;
  for (const Image& image : scene.images) derived.bytes_left += DerivedTextures::rgb_bytes(image);
  for (std::size_t i = 0; i < m.model.materials.size(); ++i)
    scene.materials.push_back(convert_material(m, int(i), scene, derived));
}

void read_textures_and_images(const ModelRef& m, Scene& scene) {
  for (std::size_t i = 0; i < m.model.images.size(); ++i) scene.images.push_back(decode_gltf_image(m, int(i)));
  for (std::size_t i = 0; i < m.model.textures.size(); ++i) {
    const tinygltf::Texture& t = m.model.textures[i];
    const std::string what = "texture " + std::to_string(i);
    Texture out;
    if (t.source >= int(m.model.images.size()))
      throw SceneError(m.file, what + ": image index " + std::to_string(t.source) + " out of range (the file has " +
                                   std::to_string(m.model.images.size()) + " images)");
    out.image = t.source < 0 ? -1 : t.source;
    if (const int webp = webp_texture_source(m, t, what); webp >= 0) out.image = webp;  // gltf_webp.h says why
    if (t.sampler >= int(m.model.samplers.size()))
      throw SceneError(m.file, what + ": sampler index " + std::to_string(t.sampler) + " out of range (the file has " +
                                   std::to_string(m.model.samplers.size()) + " samplers)");
    if (t.sampler >= 0) {
      const tinygltf::Sampler& s = m.model.samplers[std::size_t(t.sampler)];
      check_sampler(m, s, t.sampler);
      out.wrap_s = s.wrapS;
      out.wrap_t = s.wrapT;
      out.mag_filter = s.magFilter;
      out.min_filter = s.minFilter;
    }
    scene.textures.push_back(out);
  }
}

}  // namespace lancer::gltf
