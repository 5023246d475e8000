// EXT_texture_webp end to end: a mesh whose base colour, emissive (both sRGB) and
// metallic-roughness (linear) textures are lossless WebP renders exactly the image of the
// same mesh with the same texels as PNG: WebP textures take the same colour-space path.
#include <stb_image_write.h>
#include <webp/encode.h>

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gltf_mesh_scenes.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using test::lumpy_sphere;
using test::Mesh;
using test::render_lit_mesh;

constexpr int kSize = 8;

// Texture `seed`'s RGB texels, different in every texel and channel.
std::vector<unsigned char> texels(int seed) {
  std::vector<unsigned char> rgb;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x)
      for (int c = 0; c < 3; ++c)
        rgb.push_back(static_cast<unsigned char>((seed * 71 + x * 29 + y * 47 + c * 90) % 256));
  return rgb;
}

class GltfWebpRender : public gltf_test::GltfTempDir {
 protected:
  // Image `seed` as name.png or name.webp.
  std::string write_image(int seed, bool as_webp) {
    const std::vector<unsigned char> rgb = texels(seed);
    const std::string name = "tex" + std::to_string(seed) + (as_webp ? ".webp" : ".png");
    if (as_webp) {
      std::uint8_t* out = nullptr;
      const std::size_t size = WebPEncodeLosslessRGB(rgb.data(), kSize, kSize, 3 * kSize, &out);
      EXPECT_GT(size, 0u);
      gltf_test::write_file(path(name), out, size);
      WebPFree(out);
    } else {
      EXPECT_NE(stbi_write_png(path(name).c_str(), kSize, kSize, 3, rgb.data(), 3 * kSize), 0);
    }
    return name;
  }

  // The sphere with three textures; `textured` false: the same materials without them.
  std::filesystem::path write_scene(const Mesh& m, const std::string& file, bool as_webp, bool textured = true) {
    GltfBuilder b;
    json material = {{"pbrMetallicRoughness", {{"metallicFactor", 0.6}, {"roughnessFactor", 0.8}}},
                     {"emissiveFactor", {0.3, 0.3, 0.3}}};
    if (textured) {
      for (int t = 0; t < 3; ++t) {
        b.push("images", {{"uri", write_image(t, as_webp)}, {"mimeType", as_webp ? "image/webp" : "image/png"}});
        b.push("textures",
               as_webp ? json{{"extensions", {{"EXT_texture_webp", {{"source", t}}}}}} : json{{"source", t}});
      }
      material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
      material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
      material["emissiveTexture"] = {{"index", 2}};
    }
    b.push("materials", material);
    const int mesh = b.add_mesh(
        {{"POSITION", b.add_vec3(m.positions)}, {"NORMAL", b.add_vec3(m.normals)}, {"TEXCOORD_0", b.add_vec2(m.uvs)}},
        4, b.add_indices(m.indices), 0);
    b.single_node_scene(mesh);
    if (as_webp) b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_texture_webp"};
    b.write_data_uri_gltf(path(file));
    return path(file);
  }
};

TEST_F(GltfWebpRender, WebpTexturesRenderAsThePngOnes) {
  const Mesh mesh = lumpy_sphere();
  const ImageRGB png = render_lit_mesh(write_scene(mesh, "png.gltf", false));
  const ImageRGB webp = render_lit_mesh(write_scene(mesh, "webp.gltf", true));
  EXPECT_EQ(webp.rgb, png.rgb);
  // The textures count: without them the image differs.
  EXPECT_NE(render_lit_mesh(write_scene(mesh, "plain.gltf", false, false)).rgb, png.rgb);
}

}  // namespace
}  // namespace lancer
