// glTF texture references: KHR_texture_transform on every textureInfo, TEXCOORD_1,
// the textures of KHR_materials_transmission / _specular / _volume, the volume factors,
// and the errors for malformed ones.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/gltf_texture_refs.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A quad (two triangles) with TEXCOORD_0 = (x, 1 - y) and TEXCOORD_1 = (1 - x, y),
// material 0, and `textures` textures over one 1x1 BMP image.
GltfBuilder textured_quad(const json& material, int textures = 8, bool with_texcoord1 = true) {
  GltfBuilder b;
  const std::vector<glm::vec3> pos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<glm::vec2> uv0, uv1;
  for (const glm::vec3& p : pos) {
    uv0.push_back({p.x, 1 - p.y});
    uv1.push_back({1 - p.x, p.y});
  }
  json attributes = {{"POSITION", b.add_vec3(pos)}, {"TEXCOORD_0", b.add_vec2(uv0)}};
  if (with_texcoord1) attributes["TEXCOORD_1"] = b.add_vec2(uv1);
  const int indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  const std::vector<unsigned char> bmp = gltf_test::make_bmp(1, 1, {{10, 20, 30}});
  b.push("images", {{"bufferView", b.add_view(bmp.data(), bmp.size())}, {"mimeType", "image/bmp"}});
  for (int i = 0; i < textures; ++i) b.push("textures", {{"source", 0}});
  b.push("materials", material);
  b.single_node_scene(b.add_mesh(attributes, 4, indices, 0));
  return b;
}

class GltfTextures : public gltf_test::GltfTempDir {
 protected:
  Scene load(const GltfBuilder& b) {
    b.write_data_uri_gltf(path("t.gltf"));
    return read_gltf(path("t.gltf"));
  }
};

json transform(double ox, double oy, double rotation, double sx, double sy) {
  return {{"KHR_texture_transform", {{"offset", {ox, oy}}, {"rotation", rotation}, {"scale", {sx, sy}}}}};
}

// Every texture slot, texture i in slot i, each with its own transform (offset i/10).
json every_texture_material() {
  auto info = [](int index) { return json{{"index", index}, {"extensions", transform(index / 10.0, 0, 0, 1, 1)}}; };
  return {{"pbrMetallicRoughness", {{"baseColorTexture", info(0)}, {"metallicRoughnessTexture", info(1)}}},
          {"emissiveTexture", info(2)},
          {"normalTexture", info(3)},
          {"occlusionTexture", info(4)},
          {"extensions",
           {{"KHR_materials_transmission", {{"transmissionTexture", info(5)}}},
            {"KHR_materials_specular", {{"specularTexture", info(6)}, {"specularColorTexture", info(7)}}},
            {"KHR_materials_volume", {{"thicknessTexture", info(0)}}}}}};
}

TEST_F(GltfTextures, TransformIsReadOnEveryTextureReference) {
  const Scene s = load(textured_quad(every_texture_material()));
  const Material& m = s.materials.at(0);
  const TextureRef* refs[] = {&m.base_color_texture, &m.metallic_roughness_texture, &m.emissive_texture,
                              &m.normal_texture,     &m.occlusion_texture,          &m.transmission_texture,
                              &m.specular_texture,   &m.specular_color_texture};
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(refs[i]->present()) << i;
    EXPECT_EQ(refs[i]->texture, i);
    EXPECT_EQ(refs[i]->texcoord, 0);
    EXPECT_EQ(refs[i]->transform, gltf::texture_transform_matrix({float(i / 10.0), 0.0f}, 0.0f, {1.0f, 1.0f})) << i;
    EXPECT_FLOAT_EQ(refs[i]->transform[2][0], float(i / 10.0)) << "offset in the third column";
  }
  EXPECT_EQ(m.thickness_texture.texture, 0);
}

TEST_F(GltfTextures, TransformFieldsAndTexCoordOverride) {
  json material = {{"pbrMetallicRoughness",
                    {{"baseColorTexture",
                      {{"index", 0},
                       {"texCoord", 0},
                       {"extensions",
                        {{"KHR_texture_transform",
                          {{"offset", {0.25, -0.5}}, {"rotation", 0.3}, {"scale", {2, 3}}, {"texCoord", 1}}}}}}}}}};
  const Scene s = load(textured_quad(material));
  const TextureRef& ref = s.materials[0].base_color_texture;
  EXPECT_EQ(ref.texcoord, 1) << "the extension's texCoord overrides the textureInfo's";
  // T * R * S applied to (u, v, 1): scale, then rotate by 0.3 rad, then offset.
  const float c = std::cos(0.3f), sn = std::sin(0.3f);
  const glm::vec2 uv(0.4f, 0.7f);
  const glm::vec2 scaled(2 * uv.x, 3 * uv.y);
  const glm::vec2 expected(c * scaled.x + sn * scaled.y + 0.25f, -sn * scaled.x + c * scaled.y - 0.5f);
  const glm::vec3 got = ref.transform * glm::vec3(uv, 1.0f);
  EXPECT_NEAR(got.x, expected.x, 1e-6f);
  EXPECT_NEAR(got.y, expected.y, 1e-6f);
  EXPECT_EQ(got.z, 1.0f);
  EXPECT_EQ(s.materials[0].emissive_texture.transform, glm::mat3(1.0f)) << "absent texture: identity";
}

TEST_F(GltfTextures, NoTransformMeansIdentity) {
  const Scene s = load(textured_quad({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}));
  EXPECT_EQ(s.materials[0].base_color_texture.transform, glm::mat3(1.0f));
}

TEST_F(GltfTextures, Texcoord1IsReadWhenAMaterialUsesIt) {
  const Scene s = load(textured_quad({{"emissiveTexture", {{"index", 0}, {"texCoord", 1}}}}));
  ASSERT_EQ(s.triangle_count(), 2u);
  ASSERT_EQ(s.texcoords1.size(), 6u);
  ASSERT_EQ(s.texcoords.size(), 6u);
  for (std::size_t t = 0; t < 2; ++t) EXPECT_EQ(s.attrib_flags[t], kHasTexcoords | kHasTexcoords1);
  // Corner k of the quad's triangles: (0,1,2), (0,2,3).
  const glm::vec2 expected1[6] = {{1, 0}, {0, 0}, {0, 1}, {1, 0}, {0, 1}, {1, 1}};
  const glm::vec2 expected0[6] = {{0, 1}, {1, 1}, {1, 0}, {0, 1}, {1, 0}, {0, 0}};
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(s.texcoords1[k], expected1[k]) << k;
    EXPECT_EQ(s.texcoords[k], expected0[k]) << k;
  }
}

TEST_F(GltfTextures, Texcoord1IsSkippedWhenNoMaterialUsesIt) {
  const Scene s = load(textured_quad({{"emissiveTexture", {{"index", 0}}}}));
  EXPECT_TRUE(s.texcoords1.empty());
  EXPECT_EQ(s.attrib_flags[0], kHasTexcoords);
}

TEST_F(GltfTextures, Texcoord1LinesUpWhenOnlyALaterPrimitiveHasIt) {
  // Mesh 0 (plain material, drawn first) has no TEXCOORD_1 in use; mesh 1 does.
  GltfBuilder b = textured_quad({{"emissiveTexture", {{"index", 0}}}});
  const int mesh0 = 0;
  const json prim1 = {{"attributes", b.doc["meshes"][0]["primitives"][0]["attributes"]},
                      {"indices", b.doc["meshes"][0]["primitives"][0]["indices"]},
                      {"material", b.push("materials", {{"emissiveTexture", {{"index", 0}, {"texCoord", 1}}}})}};
  const int mesh1 = b.push("meshes", {{"primitives", json::array({prim1})}});
  b.set_scene({b.add_node({{"mesh", mesh0}}), b.add_node({{"mesh", mesh1}, {"translation", {0, 0, 1}}})});
  const Scene s = load(b);
  ASSERT_EQ(s.triangle_count(), 4u);
  ASSERT_EQ(s.texcoords1.size(), 12u) << "as long as texcoords";
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(s.texcoords1[k], glm::vec2(0.0f)) << "filled for the first mesh";
  EXPECT_EQ(s.texcoords1[6], glm::vec2(1, 0));
  EXPECT_EQ(s.attrib_flags[0] & kHasTexcoords1, 0);
  EXPECT_EQ(s.attrib_flags[2] & kHasTexcoords1, kHasTexcoords1);
}

TEST_F(GltfTextures, MaterialUsingAMissingTexcoord1StillLoads) {
  const Scene s = load(textured_quad({{"emissiveTexture", {{"index", 0}, {"texCoord", 1}}}}, 8, false));
  EXPECT_TRUE(s.texcoords1.empty());
  EXPECT_EQ(s.attrib_flags[0] & kHasTexcoords1, 0) << "shading reads (0, 0), as a GPU would";
}

TEST_F(GltfTextures, HigherTexcoordSetsFallBackToSet0) {
  const Scene s = load(textured_quad({{"normalTexture", {{"index", 0}, {"texCoord", 3}}}}));
  EXPECT_EQ(s.materials[0].normal_texture.texcoord, 0);
}

TEST_F(GltfTextures, ExtensionTexturesAndVolume) {
  json material = {
      {"extensions",
       {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}, {"transmissionTexture", {{"index", 1}}}}},
        {"KHR_materials_specular",
         {{"specularTexture", {{"index", 2}, {"texCoord", 1}}}, {"specularColorTexture", {{"index", 3}}}}},
        {"KHR_materials_volume",
         {{"thicknessFactor", 0.25},
          {"thicknessTexture", {{"index", 4}}},
          {"attenuationDistance", 2.5},
          {"attenuationColor", {0.5, 0.75, 1.0}}}}}}};
  const Scene s = load(textured_quad(material));
  const Material& m = s.materials[0];
  EXPECT_EQ(m.transmission, 0.5f);
  EXPECT_EQ(m.transmission_texture.texture, 1);
  EXPECT_EQ(m.specular_texture.texture, 2);
  EXPECT_EQ(m.specular_texture.texcoord, 1);
  EXPECT_EQ(m.specular_color_texture.texture, 3);
  EXPECT_EQ(m.thickness, 0.25f);
  EXPECT_EQ(m.thickness_texture.texture, 4);
  EXPECT_EQ(m.attenuation_distance, 2.5f);
  EXPECT_EQ(m.attenuation_color, glm::vec3(0.5f, 0.75f, 1.0f));
  EXPECT_EQ(s.texcoords1.size(), 6u) << "specularTexture uses set 1";
}

TEST_F(GltfTextures, VolumeDefaults) {
  const Scene s = load(textured_quad({{"extensions", {{"KHR_materials_volume", {{"thicknessFactor", 1.0}}}}}}));
  const Material& m = s.materials[0];
  EXPECT_EQ(m.thickness, 1.0f);
  EXPECT_EQ(m.attenuation_distance, std::numeric_limits<float>::infinity());
  EXPECT_EQ(m.attenuation_color, glm::vec3(1.0f));
  EXPECT_FALSE(m.thickness_texture.present());
  EXPECT_FALSE(m.transmission_texture.present());
}

TEST_F(GltfTextures, MalformedExtensionTexturesAndVolumeAreRefused) {
  auto with_ext = [](const char* ext, json value) { return json{{"extensions", {{ext, std::move(value)}}}}; };
  expect_error(textured_quad(with_ext("KHR_materials_volume", {{"attenuationDistance", 0}})),
               "attenuationDistance must be positive");
  expect_error(textured_quad(with_ext("KHR_materials_volume", {{"thicknessFactor", -1}})),
               "thicknessFactor must not be negative");
  expect_error(textured_quad(with_ext("KHR_materials_transmission", {{"transmissionTexture", {{"index", 9}}}})),
               "transmissionTexture: texture index 9 out of range (the file has 8 textures)");
  expect_error(textured_quad(with_ext("KHR_materials_specular", {{"specularTexture", {{"texCoord", 0}}}})),
               "missing property: materials[0].extensions.KHR_materials_specular.specularTexture.index");
  expect_error(textured_quad(with_ext("KHR_materials_specular", {{"specularColorTexture", 3}})),
               "specularColorTexture must be an object");
  expect_error(textured_quad(with_ext("KHR_materials_transmission", {{"transmissionTexture", {{"index", -1}}}})),
               "index must be a non-negative integer");
  expect_error(
      textured_quad(with_ext("KHR_materials_volume",
                             {{"thicknessTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", 5}}}}}})),
      "KHR_texture_transform must be an object");
}

TEST_F(GltfTextures, MalformedTransformsAreRefused) {
  auto material = [](json t) {
    return json{{"pbrMetallicRoughness",
                 {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", std::move(t)}}}}}}}};
  };
  expect_error(textured_quad(material({{"offset", {1, 2, 3}}})), "offset must be an array of 2 numbers");
  expect_error(textured_quad(material({{"scale", "big"}})), "scale must be an array of 2 numbers");
  expect_error(textured_quad(material({{"rotation", json::array({1})}})), "rotation must be a number");
  expect_error(textured_quad(material({{"texCoord", -2}})), "texCoord must be a non-negative integer");
}

TEST_F(GltfTextures, UnknownSamplerEnumsAreRefused) {
  const json material = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
  const struct {
    json sampler;
    const char* word;
  } cases[] = {{{{"wrapS", 1234}}, "sampler 0: wrapS 1234 is not one of"},
               {{{"wrapT", 10498}}, "wrapT 10498"},
               {{{"magFilter", 9984}}, "magFilter 9984"},
               {{{"minFilter", 9988}}, "minFilter 9988"}};
  for (const auto& c : cases) {
    GltfBuilder b = textured_quad(material, 1);
    b.push("samplers", c.sampler);
    b.doc["textures"][0]["sampler"] = 0;
    expect_error(b, c.word);
  }
  GltfBuilder ok = textured_quad(material, 1);
  ok.push("samplers", {{"wrapS", 33648}, {"wrapT", 33071}, {"magFilter", 9728}, {"minFilter", 9987}});
  ok.doc["textures"][0]["sampler"] = 0;
  const Scene s = load(ok);
  EXPECT_EQ(s.textures[0].wrap_s, 33648);
  EXPECT_EQ(s.textures[0].wrap_t, 33071);
  EXPECT_EQ(s.textures[0].mag_filter, 9728);
  EXPECT_EQ(s.textures[0].min_filter, 9987);
}

}  // namespace
}  // namespace lancer
