// glTF reader: materials and their extensions, textures and images, cameras,
// KHR_lights_punctual, and the same content through .gltf (data URI and external
// .bin) and .glb.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <glm/geometric.hpp>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using gltf_test::unit_triangle;

constexpr float kEps = 1e-5f;

void expect_vec3(const glm::vec3& got, const glm::vec3& want, float eps = kEps) {
  EXPECT_NEAR(got.x, want.x, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
  EXPECT_NEAR(got.y, want.y, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
  EXPECT_NEAR(got.z, want.z, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
}

class GltfContent : public gltf_test::GltfTempDir {};

// Two materials with textures and extensions, three primitives (the last without a
// material), two BMP images (one in a bufferView, one as a data URI).
GltfBuilder material_scene() {
  GltfBuilder b;
  const auto red_green = gltf_test::make_bmp(2, 1, {{255, 0, 0}, {0, 255, 0}});
  const auto blue_white = gltf_test::make_bmp(1, 2, {{0, 0, 255}, {255, 255, 255}});
  b.push("images", {{"bufferView", b.add_view(red_green.data(), red_green.size())}, {"mimeType", "image/bmp"}});
  b.push("images", {{"uri", "data:image/bmp;base64," + gltf_test::base64(blue_white)}});
  b.push("samplers", {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9987}});
  b.push("textures", {{"source", 0}, {"sampler", 0}});
  b.push("textures", {{"source", 1}});
  b.push("materials",
         {{"name", "glass"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 0.25, 0.125, 0.75}},
            {"metallicFactor", 0.3},
            {"roughnessFactor", 0.6},
            {"baseColorTexture", {{"index", 0}}},
            {"metallicRoughnessTexture", {{"index", 1}, {"texCoord", 1}}}}},
          {"emissiveFactor", {1.0, 0.5, 0.0}},
          {"emissiveTexture", {{"index", 0}}},
          {"normalTexture", {{"index", 1}, {"scale", 0.7}}},
          {"occlusionTexture", {{"index", 0}, {"strength", 0.4}}},
          {"alphaMode", "MASK"},
          {"alphaCutoff", 0.3},
          {"doubleSided", true},
          {"extensions",
           {{"KHR_materials_emissive_strength", {{"emissiveStrength", 5.0}}},
            {"KHR_materials_ior", {{"ior", 1.33}}},
            {"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
            {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {0.1, 0.2, 0.3}}}}}}});
  b.push("materials", {{"alphaMode", "BLEND"}});
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission",
                             "KHR_materials_specular"};
  const int pos = b.add_vec3(unit_triangle());
  const int nrm = b.add_vec3({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int uv = b.add_vec2({{0, 0}, {1, 0}, {0, 1}});
  const int idx = b.add_indices(std::vector<std::uint16_t>{0, 1, 2});
  const json attrs = {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}};
  const json prims = {{{"attributes", attrs}, {"indices", idx}, {"material", 0}},
                      {{"attributes", attrs}, {"material", 1}},
                      {{"attributes", attrs}}};
  b.single_node_scene(b.push("meshes", {{"primitives", prims}}));
  return b;
}

TEST_F(GltfContent, MaterialsExtensionsTexturesAndImages) {
  material_scene().write_data_uri_gltf(path("mat.gltf"));
  const Scene s = read_gltf(path("mat.gltf"));
  ASSERT_EQ(s.triangle_count(), 3u);
  ASSERT_EQ(s.materials.size(), 3u) << "two file materials plus the glTF default";
  EXPECT_EQ(s.material_id, (std::vector<std::uint32_t>{0, 1, 2}));

  const Material& m = s.materials[0];
  EXPECT_EQ(m.name, "glass");
  EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 0.125f, 0.75f));
  EXPECT_FLOAT_EQ(m.metallic, 0.3f);
  EXPECT_FLOAT_EQ(m.roughness, 0.6f);
  EXPECT_EQ(m.base_color_texture.texture, 0);
  EXPECT_EQ(m.metallic_roughness_texture.texture, 1);
  EXPECT_EQ(m.metallic_roughness_texture.texcoord, 1);
  EXPECT_EQ(m.emissive_factor, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_EQ(m.emissive_texture.texture, 0);
  EXPECT_EQ(m.normal_texture.texture, 1);
  EXPECT_FLOAT_EQ(m.normal_texture.scale, 0.7f);
  EXPECT_EQ(m.occlusion_texture.texture, 0);
  EXPECT_FLOAT_EQ(m.occlusion_texture.scale, 0.4f);
  EXPECT_EQ(m.alpha_mode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_FLOAT_EQ(m.emissive_strength, 5.0f);
  EXPECT_EQ(m.emission(), glm::vec3(5.0f, 2.5f, 0.0f));
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.transmission, 0.8f);
  EXPECT_FLOAT_EQ(m.specular, 0.5f);
  expect_vec3(m.specular_color, {0.1f, 0.2f, 0.3f});

  // Material 1: glTF defaults except alpha mode; no extension values.
  const Material& d = s.materials[1];
  EXPECT_EQ(d.alpha_mode, AlphaMode::Blend);
  EXPECT_EQ(d.base_color, glm::vec4(1.0f));
  EXPECT_EQ(d.metallic, 1.0f);
  EXPECT_EQ(d.roughness, 1.0f);
  EXPECT_FALSE(d.base_color_texture.present());
  EXPECT_FALSE(d.emissive());
  EXPECT_FLOAT_EQ(d.ior, 1.5f);
  EXPECT_EQ(d.transmission, 0.0f);
  EXPECT_FALSE(d.double_sided);
  // Material 2: the added glTF default.
  EXPECT_EQ(s.materials[2].base_color, glm::vec4(1.0f));
  EXPECT_EQ(s.materials[2].metallic, 1.0f);
  EXPECT_EQ(s.materials[2].roughness, 1.0f);

  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(s.textures[0].image, 0);
  EXPECT_EQ(s.textures[0].wrap_s, 33071);
  EXPECT_EQ(s.textures[0].wrap_t, 33648);
  EXPECT_EQ(s.textures[0].mag_filter, 9728);
  EXPECT_EQ(s.textures[0].min_filter, 9987);
  EXPECT_EQ(s.textures[1].image, 1);
  EXPECT_EQ(s.textures[1].wrap_s, 10497) << "no sampler: repeat";
  EXPECT_EQ(s.textures[1].mag_filter, -1);

  ASSERT_EQ(s.images.size(), 2u);
  EXPECT_EQ(s.images[0].width, 2);
  EXPECT_EQ(s.images[0].height, 1);
  EXPECT_EQ(s.images[0].channels, 3);
  EXPECT_EQ(s.images[0].pixels, (std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0}));
  EXPECT_EQ(s.images[1].width, 1);
  EXPECT_EQ(s.images[1].height, 2);
  EXPECT_EQ(s.images[1].pixels, (std::vector<std::uint8_t>{0, 0, 255, 255, 255, 255})) << "rows top to bottom";
}

TEST_F(GltfContent, PerspectiveCamerasInTraversalOrder) {
  GltfBuilder b;
  const double h = std::sqrt(0.5);
  b.push("cameras", {{"type", "perspective"},
                     {"name", "main"},
                     {"perspective", {{"yfov", 0.5}, {"aspectRatio", 1.5}, {"znear", 0.1}}}});
  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}}}});
  b.push("cameras",
         {{"type", "orthographic"}, {"orthographic", {{"xmag", 2.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}});
  const int second = b.add_node({{"camera", 1}, {"name", "second"}});
  const int ortho = b.add_node({{"camera", 2}});
  // 90 degrees about +y turns the view direction -z into -x.
  const int first = b.add_node({{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}});
  b.set_scene({first, ortho, second});
  b.write_data_uri_gltf(path("cam.gltf"));
  testing::internal::CaptureStderr();
  const Scene s = read_gltf(path("cam.gltf"));
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << "every camera is read, none skipped";
  // In the order the scene places them, each known by its number in the file.
  ASSERT_EQ(s.cameras.size(), 3u);
  EXPECT_EQ(s.cameras[0].index, 0);
  EXPECT_EQ(s.cameras[1].index, 2);
  EXPECT_EQ(s.cameras[2].index, 1);
  EXPECT_EQ(s.cameras[0].name, "main");
  EXPECT_FALSE(s.cameras[0].orthographic);
  EXPECT_FLOAT_EQ(s.cameras[0].yfov, 0.5f);
  ASSERT_TRUE(s.cameras[0].aspect_ratio.has_value());
  EXPECT_FLOAT_EQ(*s.cameras[0].aspect_ratio, 1.5f);
  expect_vec3(glm::vec3(s.cameras[0].camera_to_world * glm::vec4(0, 0, 0, 1)), {1, 2, 3});
  expect_vec3(glm::vec3(s.cameras[0].camera_to_world * glm::vec4(0, 0, -1, 0)), {-1, 0, 0});
  expect_vec3(glm::vec3(s.cameras[0].camera_to_world * glm::vec4(0, 1, 0, 0)), {0, 1, 0});
  EXPECT_TRUE(s.cameras[1].orthographic);
  EXPECT_FLOAT_EQ(s.cameras[1].xmag, 2.0f);
  EXPECT_FLOAT_EQ(s.cameras[1].ymag, 1.0f);
  ASSERT_TRUE(s.cameras[1].aspect_ratio.has_value());
  EXPECT_FLOAT_EQ(*s.cameras[1].aspect_ratio, 2.0f) << "xmag / ymag";
  EXPECT_EQ(s.cameras[2].name, "second") << "unnamed camera takes its node's name";
  EXPECT_FLOAT_EQ(s.cameras[2].yfov, 0.9f);
  EXPECT_FALSE(s.cameras[2].aspect_ratio.has_value());
  EXPECT_EQ(s.cameras[2].camera_to_world, glm::mat4(1.0f));
}

TEST_F(GltfContent, OrthographicCameraWithZeroMagnificationIsRefused) {
  GltfBuilder b;
  b.push("cameras", {{"type", "orthographic"}, {"orthographic", {{"xmag", 0.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}});
  b.set_scene({b.add_node({{"camera", 0}})});
  b.write_data_uri_gltf(path("zero.gltf"));
  expect_error(path("zero.gltf"), "xmag and ymag must be finite and non-zero");
}

TEST_F(GltfContent, SceneOptionChoosesAmongTheFilesScenes) {
  GltfBuilder b;
  const int a = b.add_node({{"name", "a"}, {"camera", 0}});
  const int c = b.add_node({{"name", "c"}, {"camera", 1}});
  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}});
  b.push("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}});
  b.set_scene({a});
  b.push("scenes", {{"nodes", {c}}});
  b.write_data_uri_gltf(path("two.gltf"));
  ASSERT_EQ(read_gltf(path("two.gltf")).cameras.at(0).index, 0) << "the default scene";
  ASSERT_EQ(read_gltf(path("two.gltf"), 1).cameras.at(0).index, 1) << "--scene 1";
  expect_error(path("two.gltf"), "--scene 2: the file has 2 scene(s)", 2);
}

TEST_F(GltfContent, PunctualLightsOfAllThreeTypes) {
  GltfBuilder b;
  const double h = std::sqrt(0.5);
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"name", "bulb"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 10.0}, {"range", 4.0}},
      {{"type", "spot"}, {"intensity", 20.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
      {{"type", "directional"}, {"intensity", 3.0}}};
  auto light = [](int i) { return json{{"KHR_lights_punctual", {{"light", i}}}}; };
  const int point = b.add_node({{"translation", {1, 2, 3}}, {"extensions", light(0)}});
  // -90 degrees about x: -z turns into -y (straight down).
  const int spot = b.add_node({{"translation", {0, 5, 0}}, {"rotation", {-h, 0, 0, h}}, {"extensions", light(1)}});
  // 90 degrees about y with a scale: the direction is still unit length.
  const int sun = b.add_node({{"rotation", {0, h, 0, h}}, {"scale", {3, 3, 3}}, {"extensions", light(2)}});
  b.set_scene({point, spot, sun});
  b.write_data_uri_gltf(path("lights.gltf"));
  const Scene s = read_gltf(path("lights.gltf"));
  ASSERT_EQ(s.lights.size(), 3u);

  EXPECT_EQ(s.lights[0].type, LightType::Point);
  EXPECT_EQ(s.lights[0].name, "bulb");
  EXPECT_EQ(s.lights[0].color, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(s.lights[0].intensity, 10.0f);
  EXPECT_EQ(s.lights[0].range, 4.0f);
  expect_vec3(s.lights[0].position, {1, 2, 3});

  EXPECT_EQ(s.lights[1].type, LightType::Spot);
  EXPECT_EQ(s.lights[1].color, glm::vec3(1.0f)) << "default colour";
  EXPECT_EQ(s.lights[1].intensity, 20.0f);
  EXPECT_EQ(s.lights[1].range, 0.0f) << "unlimited";
  EXPECT_FLOAT_EQ(s.lights[1].inner_cone, 0.2f);
  EXPECT_FLOAT_EQ(s.lights[1].outer_cone, 0.6f);
  expect_vec3(s.lights[1].position, {0, 5, 0});
  expect_vec3(s.lights[1].direction, {0, -1, 0});

  EXPECT_EQ(s.lights[2].type, LightType::Directional);
  EXPECT_EQ(s.lights[2].intensity, 3.0f);
  expect_vec3(s.lights[2].direction, {-1, 0, 0});
}

void expect_same_scene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.triangle_count(), b.triangle_count());
  for (std::size_t i = 0; i < a.triangle_count(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.triangles.vertex(i, k), b.triangles.vertex(i, k));
  EXPECT_EQ(a.material_id, b.material_id);
  EXPECT_EQ(a.source_triangle_id, b.source_triangle_id);
  EXPECT_EQ(a.attrib_flags, b.attrib_flags);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.texcoords, b.texcoords);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    EXPECT_EQ(a.materials[i].base_color, b.materials[i].base_color);
    EXPECT_EQ(a.materials[i].emission(), b.materials[i].emission());
    EXPECT_EQ(a.materials[i].ior, b.materials[i].ior);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) EXPECT_EQ(a.images[i].pixels, b.images[i].pixels);
}

TEST_F(GltfContent, GlbExternalBinAndDataUriGiveTheSameScene) {
  const GltfBuilder b = material_scene();
  b.write_data_uri_gltf(path("embedded.gltf"));
  b.write_external_gltf(path("external.gltf"), "external.bin");
  b.write_glb(path("binary.glb"));
  const Scene embedded = read_gltf(path("embedded.gltf"));
  ASSERT_EQ(embedded.triangle_count(), 3u);
  {
    SCOPED_TRACE("external .bin");
    expect_same_scene(embedded, read_gltf(path("external.gltf")));
  }
  {
    SCOPED_TRACE(".glb");
    expect_same_scene(embedded, read_gltf(path("binary.glb")));
  }
  {
    // The loader follows the magic, not the extension, for a .gltf holding GLB bytes.
    SCOPED_TRACE(".glb bytes named .gltf");
    b.write_glb(path("binary_named.gltf"));
    expect_same_scene(embedded, read_gltf(path("binary_named.gltf")));
  }
}

// Subnormal positions are finite: kept bit for bit (the identity transform is exact), and
// a triangle of subnormal size is not zero area (the check is in double).
TEST_F(GltfContent, SubnormalPositionsAreKept) {
  const float d = std::numeric_limits<float>::denorm_min();
  GltfBuilder b;
  b.single_node_scene(b.add_mesh(
      {{"POSITION", b.add_vec3({{1e-40f, 0, 0}, {1, -3e-42f, 0}, {0, 1, d}, {0, 0, 0}, {d, 0, 0}, {0, d, 0}})}}));
  b.write_glb(path("subnormal.glb"));
  const Scene s = read_gltf(path("subnormal.glb"));
  ASSERT_EQ(s.triangle_count(), 2u);
  EXPECT_EQ(s.triangles.vertex(0, 0), glm::vec3(1e-40f, 0, 0));
  EXPECT_EQ(s.triangles.vertex(0, 1), glm::vec3(1, -3e-42f, 0));
  EXPECT_EQ(s.triangles.vertex(0, 2), glm::vec3(0, 1, d));
  EXPECT_EQ(s.triangles.vertex(1, 1), glm::vec3(d, 0, 0));
}

TEST_F(GltfContent, SupportedRequiredExtensionsLoad) {
  GltfBuilder b = material_scene();
  b.doc["extensionsRequired"] = {"KHR_materials_ior", "KHR_texture_transform", "KHR_materials_volume"};
  b.write_data_uri_gltf(path("req.gltf"));
  EXPECT_EQ(read_gltf(path("req.gltf")).triangle_count(), 3u);
}

TEST_F(GltfContent, ExtensionsUsedButUnsupportedAreNamedInAWarning) {
  GltfBuilder b = material_scene();
  b.doc["extensionsUsed"] = {"KHR_materials_ior", "KHR_materials_iridescence", "VENDOR_made_up"};
  b.write_data_uri_gltf(path("used.gltf"));
  testing::internal::CaptureStderr();
  EXPECT_EQ(read_gltf(path("used.gltf")).triangle_count(), 3u);
  const std::string err = testing::internal::GetCapturedStderr();
  const std::string prefix = "lancer: warning: " + path("used.gltf").string() + ": extension ";
  EXPECT_NE(err.find(prefix + "KHR_materials_iridescence is not supported: the scene is rendered without it\n"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find(prefix + "VENDOR_made_up is not supported"), std::string::npos) << err;
  EXPECT_EQ(err.find("KHR_materials_ior"), std::string::npos) << "a supported extension is no news: " << err;
}

}  // namespace
}  // namespace lancer
