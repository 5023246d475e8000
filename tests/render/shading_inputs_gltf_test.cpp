// End to end: a glTF file using every texture Lancer reads (base colour, metallic-
// roughness, emissive, normal, occlusion, transmission, specular, specular colour,
// thickness), TEXCOORD_1, a texCoord override and a KHR_texture_transform, with PNGs
// written here, loaded by the reader and evaluated by evaluate_shading at the centre of
// each texel. Expected values come from the texel codes and the glTF formulas.
#include <stb_image_write.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "render/shading_inputs.h"
#include "render_test_scenes.h"
#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;

// One 2x2 test image: its file name, channel count and the code of channel ch of texel
// (x, y), chosen so that neighbouring texels and channels differ.
struct TestImage {
  const char* file;
  int channels;
  int seed;
  int code(int x, int y, int ch) const { return (seed * 37 + x * 71 + y * 113 + ch * 53 + 11) % 256; }
};

// The normal map is written apart: its texels must decode to directions above the surface.
int normal_code(int x, int y, int ch) {
  const int codes[3] = {128 + 60 * x - 30 * y, 128 - 50 * y + 20 * x, 230};
  return codes[ch];
}

double srgb(int code) {
  const double e = code / 255.0;
  return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}
double lin(int code) { return code / 255.0; }

class ShadingGltf : public gltf_test::GltfTempDir {
 protected:
  void write_png(const char* file, int channels, int (*code)(const TestImage&, int, int, int), const TestImage& img) {
    std::vector<unsigned char> pixels;
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        for (int ch = 0; ch < channels; ++ch) pixels.push_back(static_cast<unsigned char>(code(img, x, y, ch)));
    ASSERT_NE(stbi_write_png(path(file).c_str(), 2, 2, channels, pixels.data(), 2 * channels), 0) << file;
  }
};

// Images, in texture order.
const TestImage kBase{"base.png", 4, 1};
const TestImage kMetalRough{"mr.png", 3, 2};
const TestImage kEmissive{"emissive.png", 3, 3};
const TestImage kNormal{"normal.png", 3, 0};
const TestImage kTransmission{"transmission.png", 1, 5};
const TestImage kSpecular{"specular.png", 4, 6};
const TestImage kSpecularColor{"specular_color.png", 3, 7};
const TestImage kThickness{"thickness.png", 3, 8};

TEST_F(ShadingGltf, EveryTextureAtKnownUvs) {
  const TestImage images[] = {kBase, kMetalRough, kEmissive, kNormal, kTransmission, kSpecular, kSpecularColor,
                              kThickness};
  GltfBuilder b;
  for (const TestImage& img : images) {
    if (&img == &images[3])
      write_png(img.file, 3, [](const TestImage&, int x, int y, int ch) { return normal_code(x, y, ch); }, img);
    else
      write_png(img.file, img.channels, [](const TestImage& i, int x, int y, int ch) { return i.code(x, y, ch); }, img);
    b.push("images", {{"uri", img.file}});
    b.push("textures", {{"source", int(b.doc["images"].size()) - 1}, {"sampler", 0}});
  }
  b.push("samplers", {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}});

  // The unit quad in z = 0 facing +z; TEXCOORD_0 puts the image upright, TEXCOORD_1
  // mirrors it in both axes.
  const std::vector<glm::vec3> pos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<glm::vec3> nrm(4, glm::vec3(0, 0, 1));
  std::vector<glm::vec2> uv0, uv1;
  for (const glm::vec3& p : pos) {
    uv0.push_back({p.x, 1 - p.y});
    uv1.push_back({1 - p.x, p.y});
  }
  const std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
  json attributes = {{"POSITION", b.add_vec3(pos)},
                     {"NORMAL", b.add_vec3(nrm)},
                     {"TEXCOORD_0", b.add_vec2(uv0)},
                     {"TEXCOORD_1", b.add_vec2(uv1)}};
  json material = {
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {0.5, 1.0, 0.8, 0.9}},
        {"baseColorTexture", {{"index", 0}}},
        {"metallicFactor", 0.7},
        {"roughnessFactor", 0.6},
        {"metallicRoughnessTexture", {{"index", 1}}}}},
      {"emissiveFactor", {1.0, 0.5, 0.25}},
      {"emissiveTexture", {{"index", 2}, {"texCoord", 1}}},
      {"normalTexture", {{"index", 3}, {"scale", 0.8}}},
      {"occlusionTexture", {{"index", 1}, {"strength", 0.5}}},
      {"alphaMode", "BLEND"},
      {"extensions",
       {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
        {"KHR_materials_ior", {{"ior", 1.4}}},
        {"KHR_materials_transmission", {{"transmissionFactor", 0.9}, {"transmissionTexture", {{"index", 4}}}}},
        {"KHR_materials_specular",
         {{"specularFactor", 0.8},
          {"specularTexture", {{"index", 5}}},
          {"specularColorFactor", {0.9, 1.0, 0.7}},
          {"specularColorTexture",
           {{"index", 6}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}}}}}}},
        {"KHR_materials_volume",
         {{"thicknessFactor", 2.0},
          {"thicknessTexture", {{"index", 7}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}},
          {"attenuationDistance", 3.0},
          {"attenuationColor", {0.9, 0.8, 0.7}}}}}}};
  b.push("materials", material);
  b.single_node_scene(b.add_mesh(attributes, 4, b.add_indices(indices), 0));
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission",
                             "KHR_materials_specular", "KHR_materials_volume", "KHR_texture_transform"};
  b.write_data_uri_gltf(path("all_textures.gltf"));

  const Scene scene = read_gltf(path("all_textures.gltf"));
  ASSERT_EQ(scene.triangle_count(), 2u);
  ASSERT_EQ(scene.images.size(), 8u);
  ASSERT_EQ(scene.texcoords1.size(), 6u) << "the material uses TEXCOORD_1";
  EXPECT_TRUE(scene.materials[0].occlusion_texture.present());
  const BruteForce accel(scene.triangles);

  for (int ty = 0; ty < 2; ++ty)
    for (int tx = 0; tx < 2; ++tx) {
      // The centre of texel (tx, ty) under TEXCOORD_0, and where the other lookups land.
      const glm::vec2 uv(0.25f + 0.5f * tx, 0.25f + 0.5f * ty);
      const glm::vec3 at(uv.x, 1 - uv.y, 0);
      const int mx = 1 - tx, my = 1 - ty;  // texel under TEXCOORD_1
      const int ox = 1;                    // offset 0.5 in u, clamped: always the right column
      const std::string where = "texel " + std::to_string(tx) + "," + std::to_string(ty);
      const Ray ray = test::ray_from(at + glm::vec3(0, 0, 3), {0, 0, -1});
      const Hit hit = accel.intersect(ray);
      ASSERT_TRUE(hit.valid()) << where;
      const ShadingInputs si = evaluate_shading(scene, ray, hit);

      EXPECT_NEAR(si.uv0.x, uv.x, 1e-6f) << where;
      EXPECT_NEAR(si.uv0.y, uv.y, 1e-6f) << where;
      EXPECT_NEAR(si.uv1.x, 1 - uv.x, 1e-6f) << where;
      EXPECT_NEAR(si.uv1.y, 1 - uv.y, 1e-6f) << where;
      const double tol = 1e-6;
      for (int ch = 0; ch < 3; ++ch) {
        const double factor_base[3] = {0.5, 1.0, 0.8}, factor_emit[3] = {1.0, 0.5, 0.25},
                     factor_spec[3] = {0.9, 1.0, 0.7};
        EXPECT_NEAR(si.base_color[ch], factor_base[ch] * srgb(kBase.code(tx, ty, ch)), tol) << where << " ch " << ch;
        EXPECT_NEAR(si.emission[ch], factor_emit[ch] * 4.0 * srgb(kEmissive.code(mx, my, ch)), 4 * tol)
            << where << " ch " << ch;
        EXPECT_NEAR(si.specular_color[ch], factor_spec[ch] * srgb(kSpecularColor.code(ox, ty, ch)), tol)
            << where << " ch " << ch;
      }
      EXPECT_NEAR(si.alpha, 0.9 * lin(kBase.code(tx, ty, 3)), tol) << where;
      EXPECT_NEAR(si.metallic, 0.7 * lin(kMetalRough.code(tx, ty, 2)), tol) << where;
      EXPECT_NEAR(si.roughness, 0.6 * lin(kMetalRough.code(tx, ty, 1)), tol) << where;
      EXPECT_NEAR(si.transmission, 0.9 * lin(kTransmission.code(tx, ty, 0)), tol) << where;
      EXPECT_NEAR(si.specular, 0.8 * lin(kSpecular.code(tx, ty, 3)), tol) << where;
      EXPECT_NEAR(si.thickness, 2.0 * lin(kThickness.code(mx, my, 1)), 2 * tol) << where;
      EXPECT_FLOAT_EQ(si.ior, 1.4f);
      EXPECT_FLOAT_EQ(si.attenuation_distance, 3.0f);
      EXPECT_EQ(si.attenuation_color, glm::vec3(0.9f, 0.8f, 0.7f));

      // Generated tangents on the upright image: T = +x, B = +y; scale 0.8 on X and Y.
      glm::vec3 tn;
      for (int ch = 0; ch < 3; ++ch) tn[ch] = float(2.0 * lin(normal_code(tx, ty, ch)) - 1.0);
      const glm::vec3 expected = glm::normalize(tn * glm::vec3(0.8f, 0.8f, 1.0f));
      EXPECT_NEAR(si.ns.x, expected.x, 1e-5f) << where;
      EXPECT_NEAR(si.ns.y, expected.y, 1e-5f) << where;
      EXPECT_NEAR(si.ns.z, expected.z, 1e-5f) << where;
      EXPECT_EQ(si.ng, glm::vec3(0, 0, 1)) << where;
    }
}

// COLOR_0 multiplies the base colour factor (glTF 2.0, "Metallic-Roughness Material"),
// interpolated linearly over each triangle; RGB colours as normalised bytes, RGBA as floats
// whose alpha multiplies the factor's. A primitive without COLOR_0 keeps its factor.
TEST_F(ShadingGltf, VertexColoursMultiplyTheBaseColour) {
  GltfBuilder b;
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  // RGB per corner, each element padded to 4 bytes as the specification asks of attributes.
  const std::vector<std::uint8_t> bytes = {255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 255, 255, 128, 0};
  const int rgb = b.add_accessor(b.add_view(bytes.data(), bytes.size(), 4), GltfBuilder::kUByte, 4, "VEC3", true);
  const int quad_mesh = b.add_mesh({{"POSITION", b.add_vec3(quad)}, {"COLOR_0", rgb}}, 4,
                                   b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}), 0);
  // A triangle beside it (x in [2, 3]) with one RGBA colour at every corner, and one
  // further on (x in [4, 5]) without COLOR_0.
  const std::vector<glm::vec3> tri_rgba = {{2, 0, 0}, {3, 0, 0}, {3, 1, 0}}, tri_plain = {{4, 0, 0}, {5, 0, 0}, {5, 1, 0}};
  const int rgba = b.add_vec4(std::vector<glm::vec4>(3, glm::vec4(0.2f, 0.4f, 0.6f, 0.5f)));
  const int rgba_mesh = b.add_mesh({{"POSITION", b.add_vec3(tri_rgba)}, {"COLOR_0", rgba}}, 4, -1, 0);
  const int plain_mesh = b.add_mesh({{"POSITION", b.add_vec3(tri_plain)}}, 4, -1, 0);
  b.push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1.0, 0.8, 0.9}}}}, {"alphaMode", "BLEND"}});
  b.push("nodes", {{"mesh", quad_mesh}});
  b.push("nodes", {{"mesh", rgba_mesh}});
  b.push("nodes", {{"mesh", plain_mesh}});
  b.push("scenes", {{"nodes", {0, 1, 2}}});
  b.doc["scene"] = 0;
  b.write_data_uri_gltf(path("colours.gltf"));

  const Scene scene = read_gltf(path("colours.gltf"));
  ASSERT_EQ(scene.triangle_count(), 4u);
  ASSERT_EQ(scene.colors.size(), 12u);
  EXPECT_EQ(scene.attrib_flags[3] & kHasColors, 0) << "the plain triangle has no COLOR_0";
  const BruteForce accel(scene.triangles);
  const glm::vec3 factor(0.5f, 1.0f, 0.8f);
  const glm::vec3 corner[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 128.0f / 255.0f}};

  const auto shade_at = [&](glm::vec2 at) {
    const Ray ray = test::ray_from(glm::vec3(at, 3.0f), {0, 0, -1});
    const Hit hit = accel.intersect(ray);
    EXPECT_TRUE(hit.valid()) << at.x << ", " << at.y;
    return evaluate_shading(scene, ray, hit);
  };
  for (const glm::vec2 at : {glm::vec2(0.7f, 0.2f), glm::vec2(0.9f, 0.6f), glm::vec2(0.2f, 0.7f), glm::vec2(0.4f, 0.9f)}) {
    // Barycentric weights of the quad's corners: triangle (0, 1, 2) below the diagonal,
    // (0, 2, 3) above it.
    float wt[4] = {0, 0, 0, 0};
    if (at.x > at.y) {
      wt[0] = 1 - at.x, wt[1] = at.x - at.y, wt[2] = at.y;
    } else {
      wt[0] = 1 - at.y, wt[2] = at.x, wt[3] = at.y - at.x;
    }
    glm::vec3 expected(0.0f);
    for (int k = 0; k < 4; ++k) expected += wt[k] * corner[k];
    const ShadingInputs si = shade_at(at);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(si.base_color[ch], factor[ch] * expected[ch], 1e-5f) << at.x << ", " << at.y;
    EXPECT_NEAR(si.alpha, 0.9f, 1e-6f) << "RGB colours leave alpha alone";
  }
  const ShadingInputs with_alpha = shade_at({2.8f, 0.3f});
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(with_alpha.base_color[ch], factor[ch] * (0.2f * float(ch + 1)), 1e-6f);
  EXPECT_NEAR(with_alpha.alpha, 0.9f * 0.5f, 1e-6f);
  const ShadingInputs plain = shade_at({4.8f, 0.3f});
  for (int ch = 0; ch < 3; ++ch) EXPECT_FLOAT_EQ(plain.base_color[ch], factor[ch]);
}

}  // namespace
}  // namespace lancer
