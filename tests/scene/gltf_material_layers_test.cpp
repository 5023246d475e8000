// glTF reading of KHR_materials_clearcoat, KHR_materials_sheen, KHR_materials_unlit and the
// conversion of KHR_materials_pbrSpecularGlossiness: factors, textures (channel, texCoord,
// normal scale), the extensions' defaults, and that files requiring them load.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"
#include "scene/scene_warning.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// One triangle with TEXCOORD_0/1, material 0 = `material`, four textures over one image.
GltfBuilder triangle_with(const json& material, const std::vector<std::string>& required = {}) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uv = b.add_vec2({{0, 0}, {1, 0}, {0, 1}});
  const std::vector<unsigned char> bmp = gltf_test::make_bmp(1, 1, {{10, 20, 30}});
  b.push("images", {{"bufferView", b.add_view(bmp.data(), bmp.size())}, {"mimeType", "image/bmp"}});
  for (int i = 0; i < 4; ++i) b.push("textures", {{"source", 0}});
  b.push("materials", material);
  b.single_node_scene(b.add_mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}, {"TEXCOORD_1", uv}}, 4, -1, 0));
  if (!required.empty()) {
    b.doc["extensionsUsed"] = required;
    b.doc["extensionsRequired"] = required;
  }
  return b;
}

class GltfMaterialLayers : public gltf_test::GltfTempDir {
 protected:
  Material load(const GltfBuilder& b) {
    b.write_data_uri_gltf(path("m.gltf"));
    const Scene s = read_gltf(path("m.gltf"));
    return s.materials.at(0);
  }
};

TEST_F(GltfMaterialLayers, ClearcoatFactorsAndTextures) {
  const Material m = load(triangle_with(
      {{"extensions",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 0.75},
           {"clearcoatTexture", {{"index", 1}}},
           {"clearcoatRoughnessFactor", 0.3},
           {"clearcoatRoughnessTexture", {{"index", 2}, {"texCoord", 1}}},
           {"clearcoatNormalTexture", {{"index", 3}, {"scale", 0.5}}}}}}}},
      {"KHR_materials_clearcoat"}));
  EXPECT_FLOAT_EQ(m.clearcoat, 0.75f);
  EXPECT_EQ(m.clearcoat_texture.texture, 1);
  EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.3f);
  EXPECT_EQ(m.clearcoat_roughness_texture.texture, 2);
  EXPECT_EQ(m.clearcoat_roughness_texture.texcoord, 1);
  EXPECT_EQ(m.clearcoat_normal_texture.texture, 3);
  EXPECT_FLOAT_EQ(m.clearcoat_normal_texture.scale, 0.5f);
  EXPECT_FALSE(m.normal_texture.present()) << "the coat's normal map is not the base's";
  EXPECT_TRUE(m.uses_texcoord(1));
}

TEST_F(GltfMaterialLayers, ClearcoatDefaults) {
  const Material m = load(triangle_with({{"extensions", {{"KHR_materials_clearcoat", json::object()}}}}));
  EXPECT_EQ(m.clearcoat, 0.0f);
  EXPECT_EQ(m.clearcoat_roughness, 0.0f);
  EXPECT_FALSE(m.clearcoat_texture.present());
  EXPECT_FALSE(m.clearcoat_normal_texture.present());
  const Material plain = load(triangle_with(json::object()));
  EXPECT_EQ(plain.clearcoat, 0.0f);
  EXPECT_EQ(plain.sheen_color, glm::vec3(0.0f));
  EXPECT_FALSE(plain.unlit);
}

TEST_F(GltfMaterialLayers, SheenFactorsAndTextures) {
  const Material m = load(triangle_with({{"extensions",
                                          {{"KHR_materials_sheen",
                                            {{"sheenColorFactor", {0.9, 0.1, 0.2}},
                                             {"sheenColorTexture", {{"index", 2}}},
                                             {"sheenRoughnessFactor", 0.4},
                                             {"sheenRoughnessTexture", {{"index", 3}}}}}}}},
                                        {"KHR_materials_sheen"}));
  EXPECT_EQ(m.sheen_color, glm::vec3(0.9f, 0.1f, 0.2f));
  EXPECT_EQ(m.sheen_color_texture.texture, 2);
  EXPECT_FLOAT_EQ(m.sheen_roughness, 0.4f);
  EXPECT_EQ(m.sheen_roughness_texture.texture, 3);
  const Material d = load(triangle_with({{"extensions", {{"KHR_materials_sheen", json::object()}}}}));
  EXPECT_EQ(d.sheen_color, glm::vec3(0.0f)) << "the extension's default colour is black: no sheen";
  EXPECT_EQ(d.sheen_roughness, 0.0f);
}

TEST_F(GltfMaterialLayers, WrongTypesAreRefused) {
  EXPECT_THROW(load(triangle_with({{"extensions", {{"KHR_materials_sheen", {{"sheenColorFactor", 1.0}}}}}})),
               SceneError);
  EXPECT_THROW(load(triangle_with({{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", "x"}}}}}})),
               SceneError);
  EXPECT_THROW(load(triangle_with({{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatTexture", {{"index", 9}}}}}}}})),
               SceneError);
}

TEST_F(GltfMaterialLayers, Unlit) {
  const Material m = load(triangle_with(
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}}, {"extensions", {{"KHR_materials_unlit", json::object()}}}},
      {"KHR_materials_unlit"}));
  EXPECT_TRUE(m.unlit);
  EXPECT_EQ(m.base_color, glm::vec4(0.2f, 0.4f, 0.6f, 1.0f));
}

TEST_F(GltfMaterialLayers, SpecularGlossinessIsConverted) {
  const Material m = load(triangle_with({{"extensions",
                                          {{"KHR_materials_pbrSpecularGlossiness",
                                            {{"diffuseFactor", {0.5, 0.25, 0.125, 0.8}},
                                             {"diffuseTexture", {{"index", 1}}},
                                             {"specularFactor", {0.04, 0.05, 0.06}},
                                             {"glossinessFactor", 0.7},
                                             {"specularGlossinessTexture", {{"index", 2}}}}}}}},
                                        {"KHR_materials_pbrSpecularGlossiness"}));
  EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 0.125f, 0.8f));
  EXPECT_EQ(m.base_color_texture.texture, 1);
  EXPECT_EQ(m.metallic, 0.0f);
  // The BMP has no alpha: glossiness 1, so the derived texture's roughness is 1 - 0.7.
  ASSERT_TRUE(m.metallic_roughness_texture.present());
  EXPECT_NE(m.metallic_roughness_texture.texture, 2) << "a texture of its own";
  EXPECT_EQ(m.roughness, 1.0f);
  // f0 = dielectric_f0(ior) * specular_color = specularFactor: ior 0 gives dielectric_f0 = 1.
  EXPECT_EQ(m.ior, 0.0f);
  EXPECT_EQ(m.specular, 1.0f);
  EXPECT_EQ(m.specular_color, glm::vec3(0.04f, 0.05f, 0.06f));
  EXPECT_EQ(m.specular_color_texture.texture, 2);

  const Material d = load(triangle_with({{"extensions", {{"KHR_materials_pbrSpecularGlossiness", json::object()}}}}));
  EXPECT_FALSE(d.metallic_roughness_texture.present());
  EXPECT_EQ(d.base_color, glm::vec4(1.0f));
  EXPECT_EQ(d.roughness, 0.0f) << "glossiness 1 by default";
  EXPECT_EQ(d.specular_color, glm::vec3(1.0f));
  EXPECT_EQ(d.metallic, 0.0f);
}

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
}

// specularGlossinessTexture's alpha is the glossiness: roughness = 1 - glossinessFactor * A,
// texel by texel, in a derived texture with the source's texCoord and transform; two
// materials with the same texture and factor share it. Derived textures take at most one
// RGB copy of the file's images: another factor on the same (only) image is refused with a
// warning and keeps the factor alone.
TEST_F(GltfMaterialLayers, SpecularGlossinessTextureAlphaBecomesRoughness) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uv = b.add_vec2({{0, 0}, {1, 0}, {0, 1}});
  // Three texels: glossiness A = 0, 128, 255 under specular RGB (10, 20, 30).
  const std::vector<unsigned char> rgba = {10, 20, 30, 0, 10, 20, 30, 128, 10, 20, 30, 255};
  std::vector<unsigned char> png;
  ASSERT_NE(stbi_write_png_to_func(append_bytes, &png, 3, 1, 4, rgba.data(), 12), 0);
  b.push("images", {{"bufferView", b.add_view(png.data(), png.size())}, {"mimeType", "image/png"}});
  b.push("textures", {{"source", 0}});
  const auto spec_gloss = [](double glossiness) {
    return json{{"extensions",
                 {{"KHR_materials_pbrSpecularGlossiness",
                   {{"glossinessFactor", glossiness},
                    {"specularGlossinessTexture", {{"index", 0}, {"texCoord", 1}}}}}}}};
  };
  b.push("materials", spec_gloss(0.6));
  b.push("materials", spec_gloss(0.6));
  b.push("materials", spec_gloss(1.0));
  std::vector<int> nodes;
  for (int i = 0; i < 3; ++i) {
    const int mesh = b.add_mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}, {"TEXCOORD_1", uv}}, 4, -1, i);
    nodes.push_back(b.add_node({{"mesh", mesh}}));
  }
  b.set_scene(nodes);
  b.write_data_uri_gltf(path("sg.gltf"));
  SceneWarningLog log;
  const Scene s = read_gltf(path("sg.gltf"));
  const std::vector<std::string> warnings = log.take();
  ASSERT_EQ(s.materials.size(), 3u);
  const Material& m = s.materials[0];
  ASSERT_TRUE(m.metallic_roughness_texture.present());
  EXPECT_EQ(m.metallic_roughness_texture.texcoord, 1);
  EXPECT_EQ(m.roughness, 1.0f);
  EXPECT_EQ(m.metallic, 0.0f);
  EXPECT_EQ(m.specular_color_texture.texture, 0) << "the colour still comes from the file's texture";
  const Image& img = s.images.at(std::size_t(s.textures.at(std::size_t(m.metallic_roughness_texture.texture)).image));
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.channels, 3);
  // G = round(255 (1 - 0.6 A / 255)): 255, 178, 102; B (metallic) 0.
  EXPECT_EQ(img.pixels[1], 255);
  EXPECT_EQ(img.pixels[4], 178);
  EXPECT_EQ(img.pixels[7], 102);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(img.pixels[std::size_t(i) * 3 + 2], 0);
  EXPECT_EQ(s.materials[1].metallic_roughness_texture.texture, m.metallic_roughness_texture.texture);
  EXPECT_EQ(s.images.size(), 2u) << "one derived image";
  EXPECT_FALSE(s.materials[2].metallic_roughness_texture.present());
  EXPECT_EQ(s.materials[2].roughness, 0.0f);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("materials[2]"), std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace lancer
