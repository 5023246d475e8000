// EXT_texture_webp: a texture whose extension names a WebP image (encoded here with
// libwebp's lossless encoder) gets that image's pixels, from a file, a bufferView or a data
// URI, in preference to a PNG fallback; WebP is read through the OBJ reader too. Corrupt,
// truncated and hostile WebP data and malformed extensions are refused naming the file
// and the image or texture.
#include <webp/encode.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/image_decode.h"
#include "scene/obj_reader.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using gltf_test::GltfBuilder;
using gltf_test::json;
using Bytes = std::vector<unsigned char>;

constexpr const char* kExt = "EXT_texture_webp";

// A w x h image with `channels` (3 or 4) channels whose texels all differ.
Bytes texels(int w, int h, int channels) {
  Bytes out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)
        out.push_back(static_cast<unsigned char>(c == 3 ? 40 + 50 * x + 3 * y : (x * 60 + y * 23 + c * 85) & 255));
  return out;
}

// Lossless WebP, so the decoded texels are the encoded ones.
Bytes webp(const Bytes& pixels, int w, int h, int channels) {
  std::uint8_t* out = nullptr;
  const std::size_t size = channels == 4 ? WebPEncodeLosslessRGBA(pixels.data(), w, h, w * 4, &out)
                                         : WebPEncodeLosslessRGB(pixels.data(), w, h, w * 3, &out);
  EXPECT_GT(size, 0u);
  Bytes bytes(out, out + size);
  WebPFree(out);
  return bytes;
}

// A textured quad: material 0's base colour is texture 0, whose image is given by
// `texture` (an object with "source" and/or "extensions").
GltfBuilder quad(const json& texture) {
  GltfBuilder b;
  const int pos = b.add_vec3({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int uv = b.add_vec2({{0, 1}, {1, 1}, {1, 0}, {0, 0}});
  const int idx = b.add_indices(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  b.push("textures", texture);
  b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.single_node_scene(b.add_mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, 4, idx, 0));
  return b;
}

json webp_texture(int image) { return {{"extensions", {{kExt, {{"source", image}}}}}}; }

void require_webp(GltfBuilder& b) { b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {kExt}; }

class GltfWebp : public gltf_test::GltfTempDir {
 protected:
  void write(const std::string& name, const Bytes& bytes) {
    gltf_test::write_file(path(name), bytes.data(), bytes.size());
  }
  // The image the base colour of `s` samples.
  static const Image& base_color_image(const Scene& s) {
    return s.images.at(std::size_t(s.textures.at(std::size_t(s.materials.at(0).base_color_texture.texture)).image));
  }
};

TEST_F(GltfWebp, TextureGetsTheWebpImagesTexels) {
  const Bytes rgb = texels(5, 3, 3), rgba = texels(4, 4, 4);
  write("rgb.webp", webp(rgb, 5, 3, 3));
  write("rgba.webp", webp(rgba, 4, 4, 4));
  GltfBuilder b = quad(webp_texture(0));
  b.push("images", {{"uri", "rgb.webp"}, {"mimeType", "image/webp"}});
  require_webp(b);
  b.write_data_uri_gltf(path("rgb.gltf"));
  const Scene scene = read_supported(path("rgb.gltf"));
  const Image& opaque = base_color_image(scene);
  EXPECT_EQ(opaque.width, 5);
  EXPECT_EQ(opaque.height, 3);
  EXPECT_EQ(opaque.channels, 3);
  EXPECT_EQ(opaque.pixels, rgb);
  EXPECT_EQ(opaque.name, "rgb.webp");
  b.doc["images"][0]["uri"] = "rgba.webp";
  b.write_data_uri_gltf(path("rgba.gltf"));
  const Scene s = read_supported(path("rgba.gltf"));
  EXPECT_EQ(base_color_image(s).channels, 4) << "alpha is kept";
  EXPECT_EQ(base_color_image(s).pixels, rgba);
}

// In a bufferView (as a .glb holds it) and as a data URI, whose media type tinygltf 2.7
// does not know.
TEST_F(GltfWebp, EmbeddedImagesDecode) {
  const Bytes rgb = texels(6, 2, 3), encoded = webp(rgb, 6, 2, 3);
  GltfBuilder b = quad(webp_texture(0));
  b.push("images", {{"bufferView", b.add_view(encoded.data(), encoded.size())}, {"mimeType", "image/webp"}});
  require_webp(b);
  b.write_glb(path("view.glb"));
  EXPECT_EQ(base_color_image(read_supported(path("view.glb"))).pixels, rgb);
  b.doc["images"][0] = {{"uri", "data:image/webp;base64," + gltf_test::base64(encoded)}};
  b.write_data_uri_gltf(path("uri.gltf"));
  b.write_glb(path("uri.glb"));
  EXPECT_EQ(base_color_image(read_supported(path("uri.gltf"))).pixels, rgb);
  EXPECT_EQ(base_color_image(read_supported(path("uri.glb"))).pixels, rgb);
}

// The WebP image is preferred to the texture's own source, a PNG-style fallback (a BMP
// here), in a file that only uses the extension.
TEST_F(GltfWebp, WebpIsPreferredToTheFallback) {
  const Bytes rgb = texels(2, 2, 3);
  write("tex.webp", webp(rgb, 2, 2, 3));
  const Bytes bmp = gltf_test::make_bmp(1, 1, {{200, 10, 10}});
  write("fallback.bmp", bmp);
  json texture = webp_texture(1);
  texture["source"] = 0;
  GltfBuilder b = quad(texture);
  b.push("images", {{"uri", "fallback.bmp"}});
  b.push("images", {{"uri", "tex.webp"}});
  b.doc["extensionsUsed"] = {kExt};
  b.write_data_uri_gltf(path("both.gltf"));
  const Scene s = read_supported(path("both.gltf"));
  EXPECT_EQ(s.textures.at(0).image, 1);
  EXPECT_EQ(base_color_image(s).pixels, rgb);
  // Without the extension the same texture takes its fallback.
  b.doc["textures"][0].erase("extensions");
  b.write_data_uri_gltf(path("fallback.gltf"));
  EXPECT_EQ(read_gltf(path("fallback.gltf")).textures.at(0).image, 0);
}

TEST_F(GltfWebp, BadWebpDataIsRefusedNamingTheImage) {
  const Bytes good = webp(texels(16, 16, 3), 16, 16, 3);
  GltfBuilder b = quad(webp_texture(0));
  b.push("images", {{"uri", "bad.webp"}});
  require_webp(b);
  b.write_data_uri_gltf(path("scene.gltf"));
  write("bad.webp", Bytes(good.begin(), good.begin() + std::ptrdiff_t(good.size() / 2)));
  expect_error(path("scene.gltf"), "image 0 ('bad.webp') cannot be decoded: truncated WebP");
  Bytes corrupt = good;
  for (std::size_t k = 30; k < corrupt.size(); k += 3) corrupt[k] ^= 0x5A;
  write("bad.webp", corrupt);
  expect_error(path("scene.gltf"), "image 0 ('bad.webp') cannot be decoded");
  // A lossless header claiming 16383 x 16383 texels, then garbage: refused without a
  // gigabyte of pixels being allocated first.
  Bytes hostile = {'R', 'I', 'F', 'F', 32, 0, 0, 0, 'W', 'E', 'B', 'P', 'V', 'P', '8', 'L', 20, 0, 0, 0, 0x2f};
  const std::uint32_t size_bits = 16382u | 16382u << 14;
  for (int k = 0; k < 4; ++k) hostile.push_back(static_cast<unsigned char>(size_bits >> (8 * k)));
  hostile.resize(40, 0x33);
  write("bad.webp", hostile);
  expect_error(path("scene.gltf"), "image 0 ('bad.webp') cannot be decoded: corrupt WebP data");
}

TEST_F(GltfWebp, MalformedExtensionsAreRefused) {
  GltfBuilder b = quad(webp_texture(3));
  const Bytes encoded = webp(texels(2, 2, 3), 2, 2, 3);
  b.push("images", {{"bufferView", b.add_view(encoded.data(), encoded.size())}, {"mimeType", "image/webp"}});
  require_webp(b);
  expect_error(b, "texture 0 EXT_texture_webp: image index 3 out of range (the file has 1 images)");
  b.doc["textures"][0]["extensions"][kExt] = {{"image", 0}};
  expect_error(b, "texture 0 EXT_texture_webp must be an object with a 'source' image index");
  b.doc["textures"][0]["extensions"][kExt]["source"] = "0";
  expect_error(b, "wrong JSON type: textures[0].extensions.EXT_texture_webp.source");
}

TEST(WebpDecode, ObjTexturesAndDecodeImageReadWebp) {
  const Bytes rgba = texels(3, 5, 4);
  const Image image = decode_image(webp(rgba, 3, 5, 4), "t.webp", "scene.obj", "texture 't.webp'");
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.height, 5);
  EXPECT_EQ(image.pixels, rgba);
  // "RIFF" with another form type is not WebP: stb_image then refuses it.
  EXPECT_THROW(decode_image(Bytes{'R', 'I', 'F', 'F', 4, 0, 0, 0, 'W', 'A', 'V', 'E'}, "x", "f", "image 0"),
               SceneError);
}

class ObjWebp : public gltf_test::GltfTempDir {};

TEST_F(ObjWebp, MapKdMayBeWebp) {
  const Bytes rgb = texels(2, 3, 3);
  const Bytes encoded = webp(rgb, 2, 3, 3);
  gltf_test::write_file(path("tex.webp"), encoded.data(), encoded.size());
  gltf_test::write_text(path("scene.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd tex.webp\n");
  gltf_test::write_text(
      path("scene.obj"),
      "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n");
  const Scene s = read_obj(path("scene.obj"));
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].pixels, rgb);
}

}  // namespace
}  // namespace lancer
