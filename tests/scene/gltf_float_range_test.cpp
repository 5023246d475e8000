// glTF numbers beyond float's range (issue 7: NaN and Inf never reach a scene). JSON has
// no infinities, but 1e39 parses as a double and becomes +inf when stored as a float: every
// such factor of a material, a texture reference (scale, KHR_texture_transform) or a light
// must be refused with the file and the material or light named, and the same value within
// float's range must still load (so the tests can fail). Found by the fuzz target's
// scene checks (tests/fuzz/fuzz_support.h).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// A textured quad (one 1x1 BMP) with `material`, plus `lights` hung on a second node.
GltfBuilder quad(const json& material, const json& lights = nullptr) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int uv = b.add_vec2({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const int indices = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  const std::vector<unsigned char> bmp = gltf_test::make_bmp(1, 1, {{10, 20, 30}});
  b.push("images", {{"bufferView", b.add_view(bmp.data(), bmp.size())}, {"mimeType", "image/bmp"}});
  b.push("textures", {{"source", 0}});
  b.push("materials", material);
  const int mesh = b.add_mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, 4, indices, 0);
  if (lights.is_null()) {
    b.single_node_scene(mesh);
  } else {
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = lights;
    const int shape = b.add_node({{"mesh", mesh}});
    const int lamp = b.add_node({{"translation", {0, 2, 2}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.set_scene({shape, lamp});
  }
  return b;
}

json transform(double offset, double rotation, double scale) {
  return {{"KHR_texture_transform", {{"offset", {offset, 0}}, {"rotation", rotation}, {"scale", {scale, 1}}}}};
}

// Materials with one number set to `x`: in range they load, at 1e39 they must not.
std::vector<std::pair<std::string, json>> materials(double x) {
  return {
      {"baseColorFactor", {{"pbrMetallicRoughness", {{"baseColorFactor", {x, 1, 1, 1}}}}}},
      {"metallicFactor", {{"pbrMetallicRoughness", {{"metallicFactor", x}}}}},
      {"emissiveFactor", {{"emissiveFactor", {x, 0, 0}}}},
      {"emissiveStrength",
       {{"emissiveFactor", {1, 1, 1}}, {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", x}}}}}}},
      {"alphaCutoff", {{"alphaCutoff", x}}},
      {"ior", {{"extensions", {{"KHR_materials_ior", {{"ior", x}}}}}}},
      {"specularColorFactor", {{"extensions", {{"KHR_materials_specular", {{"specularColorFactor", {x, 1, 1}}}}}}}},
      {"thicknessFactor", {{"extensions", {{"KHR_materials_volume", {{"thicknessFactor", x}}}}}}},
      {"attenuationColor", {{"extensions", {{"KHR_materials_volume", {{"attenuationColor", {x, 1, 1}}}}}}}},
      {"clearcoatFactor", {{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", x}}}}}}},
      {"sheenColorFactor", {{"extensions", {{"KHR_materials_sheen", {{"sheenColorFactor", {x, 1, 1}}}}}}}},
      {"sheenRoughnessFactor", {{"extensions", {{"KHR_materials_sheen", {{"sheenRoughnessFactor", x}}}}}}},
      {"normalTexture scale", {{"normalTexture", {{"index", 0}, {"scale", x}}}}},
      {"texture offset",
       {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", transform(x, 0, 1)}}}}}}},
      {"texture rotation",
       {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", transform(0, x, 1)}}}}}}},
      {"texture scale",
       {{"extensions",
         {{"KHR_materials_transmission",
           {{"transmissionTexture", {{"index", 0}, {"extensions", transform(0, 0, x)}}}}}}}}},
  };
}

std::vector<std::pair<std::string, json>> lights(double x) {
  return {
      {"color", json::array({{{"type", "point"}, {"color", {x, 1, 1}}}})},
      {"intensity", json::array({{{"type", "point"}, {"intensity", x}}})},
      {"range", json::array({{{"type", "point"}, {"range", x}}})},
  };
}

class GltfFloatRange : public gltf_test::GltfTempDir {
 protected:
  void expect_refused(const GltfBuilder& b, const std::string& label, const std::string& word) {
    b.write_data_uri_gltf(path("big.gltf"));
    try {
      const Scene s = read_gltf(path("big.gltf"));
      ADD_FAILURE() << label << " of 1e39 loaded";
    } catch (const SceneError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path("big.gltf").string()), std::string::npos) << label << ": " << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << label << ": " << msg;
      EXPECT_NE(msg.find("beyond the range of float"), std::string::npos) << label << ": " << msg;
    }
  }
  void expect_loads(const GltfBuilder& b, const std::string& label) {
    b.write_data_uri_gltf(path("ok.gltf"));
    EXPECT_NO_THROW((void)read_gltf(path("ok.gltf"))) << label;
  }
};

TEST_F(GltfFloatRange, MaterialFactorsAndTextureTransformsBeyondFloatAreRefused) {
  for (const auto& [label, material] : materials(1e39)) expect_refused(quad(material), label, "material 0");
  for (const auto& [label, material] : materials(2.0)) expect_loads(quad(material), label);
}

TEST_F(GltfFloatRange, LightParametersBeyondFloatAreRefused) {
  for (const auto& [label, l] : lights(1e39)) expect_refused(quad(json::object(), l), label, "light 0");
  for (const auto& [label, l] : lights(2.0)) expect_loads(quad(json::object(), l), label);
  // Each finite, the product overflowing: the light's radiant intensity is still infinite.
  expect_refused(quad(json::object(), json::array({{{"type", "point"}, {"color", {3e38, 1, 1}}, {"intensity", 10}}})),
                 "color times intensity", "light 0");
}

}  // namespace
}  // namespace lancer
