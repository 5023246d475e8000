// Texture image files: missing, corrupt and truncated PNGs and JPEGs are refused at load
// time with a message naming the scene file and the image, through the glTF and OBJ
// readers and through decode_image() itself. Images are encoded here with
// stb_image_write; no binary fixtures.
#include <stb_image_write.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene/gltf_reader.h"
#include "scene/gltf_test_files.h"
#include "scene/image_decode.h"
#include "scene/obj_reader.h"
#include "scene/scene_error.h"

namespace lancer {
namespace {

using Bytes = std::vector<unsigned char>;

void append(void* context, void* data, int size) {
  auto* out = static_cast<Bytes*>(context);
  const auto* p = static_cast<const unsigned char*>(data);
  out->insert(out->end(), p, p + size);
}

// A w x h RGB gradient.
Bytes pixels(int w, int h) {
  Bytes rgb;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) rgb.push_back(static_cast<unsigned char>((x * 16 + y * 5 + c * 80) & 255));
  return rgb;
}

Bytes png(int w = 8, int h = 8) {
  Bytes out;
  const Bytes rgb = pixels(w, h);
  EXPECT_NE(stbi_write_png_to_func(append, &out, w, h, 3, rgb.data(), 3 * w), 0);
  return out;
}

Bytes jpeg(int w = 16, int h = 16) {
  Bytes out;
  const Bytes rgb = pixels(w, h);
  EXPECT_NE(stbi_write_jpg_to_func(append, &out, w, h, 3, rgb.data(), 90), 0);
  return out;
}

Bytes cut(const Bytes& b, std::size_t n) { return Bytes(b.begin(), b.begin() + std::ptrdiff_t(n)); }

// decode_image must throw SceneError naming the file and the image; returns the message.
std::string decode_error(const Bytes& bytes) {
  try {
    const Image image = decode_image(bytes, "img", "scene.gltf", "image 7");
    ADD_FAILURE() << "decoded a " << image.width << "x" << image.height << " image from " << bytes.size() << " bytes";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("scene.gltf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("image 7"), std::string::npos) << msg;
    return msg;
  }
  return "";
}

TEST(ImageDecode, CompletePngAndJpegDecode) {
  const Image p = decode_image(png(), "p.png", "f", "image");
  EXPECT_EQ(p.width, 8);
  EXPECT_EQ(p.height, 8);
  EXPECT_EQ(p.channels, 3);
  EXPECT_EQ(p.pixels, pixels(8, 8)) << "PNG is lossless";
  EXPECT_EQ(p.name, "p.png");
  const Image j = decode_image(jpeg(), "j.jpg", "f", "image");
  EXPECT_EQ(j.width, 16);
  EXPECT_EQ(j.channels, 3);
  EXPECT_EQ(truncation_problem(png()), "");
  EXPECT_EQ(truncation_problem(jpeg()), "");
}

TEST(ImageDecode, EveryTruncatedPngIsRefused) {
  const Bytes whole = png();
  for (std::size_t n = 0; n < whole.size(); ++n) {
    const std::string msg = decode_error(cut(whole, n));
    if (n >= 33) {  // signature + IHDR: stb reads the header, the chunk walk finds the cut
      EXPECT_NE(msg.find("truncated PNG"), std::string::npos) << n << ": " << msg;
    }
  }
}

TEST(ImageDecode, EveryTruncatedJpegIsRefused) {
  const Bytes whole = jpeg();
  ASSERT_EQ(whole[whole.size() - 2], 0xFF);
  ASSERT_EQ(whole.back(), 0xD9) << "stb writes EOI last";
  std::size_t sos = 0;  // the start-of-scan marker: from there on only EOI is missing
  for (std::size_t i = 2; i + 1 < whole.size() && !sos; ++i)
    if (whole[i] == 0xFF && whole[i + 1] == 0xDA) sos = i;
  ASSERT_GT(sos, 0u);
  for (std::size_t n = 0; n < whole.size(); ++n) {
    const std::string msg = decode_error(cut(whole, n));
    if (n > sos + 2) {
      EXPECT_NE(msg.find("no end-of-image marker (0xFFD9)"), std::string::npos) << n << ": " << msg;
    }
  }
}

TEST(ImageDecode, JpegWithBytesAfterEoiIsAccepted) {
  Bytes b = jpeg();
  b.insert(b.end(), {0x00, 0x00, 0x12, 0x34});
  EXPECT_EQ(truncation_problem(b), "");
  EXPECT_EQ(decode_image(b, "j", "f", "image").width, 16);
}

TEST(ImageDecode, ThumbnailEoiInsideAnAppSegmentDoesNotCount) {
  // An APP1 segment holding a complete small JPEG (as EXIF thumbnails are), inserted
  // after SOI: its EOI lies inside the segment and must not end the walk.
  const Bytes thumb = jpeg(8, 8), main = jpeg();
  Bytes segment = {0xFF, 0xE1, 0, 0, 'E', 'x', 'i', 'f', 0, 0};
  segment.insert(segment.end(), thumb.begin(), thumb.end());
  const std::size_t length = segment.size() - 2;
  segment[2] = static_cast<unsigned char>(length >> 8);
  segment[3] = static_cast<unsigned char>(length & 255);
  Bytes with_thumb(main.begin(), main.begin() + 2);
  with_thumb.insert(with_thumb.end(), segment.begin(), segment.end());
  with_thumb.insert(with_thumb.end(), main.begin() + 2, main.end());
  EXPECT_EQ(truncation_problem(with_thumb), "");
  EXPECT_EQ(decode_image(with_thumb, "j", "f", "image").width, 16);
  const Bytes truncated = cut(with_thumb, with_thumb.size() - 40);
  EXPECT_NE(truncation_problem(truncated), "");
  decode_error(truncated);
}

TEST(ImageDecode, CorruptAndEmptyDataAreRefused) {
  // Intact chunk structure, scrambled compressed data: the IDAT data runs from byte 41
  // (signature 8, IHDR 25, IDAT length and type 8) to its CRC before the 12-byte IEND.
  Bytes garbage = png();
  for (std::size_t i = 41; i + 16 < garbage.size(); ++i) garbage[i] = static_cast<unsigned char>(i * 7);
  EXPECT_EQ(truncation_problem(garbage), "");
  EXPECT_NE(decode_error(garbage).find("cannot be decoded"), std::string::npos);
  EXPECT_NE(decode_error({}).find("no data"), std::string::npos);
  EXPECT_NE(decode_error({'h', 'e', 'l', 'l', 'o'}).find("cannot be decoded"), std::string::npos);
  EXPECT_EQ(truncation_problem(Bytes{'B', 'M'}), "") << "neither PNG nor JPEG: left to stb";
}

// The same checks through the readers, with the images as files beside the scene.
class TextureFiles : public gltf_test::GltfTempDir {
 protected:
  // A one-triangle glTF whose base colour texture is the image file `image`.
  std::filesystem::path gltf_with_image(const std::string& image) {
    gltf_test::GltfBuilder b;
    const int pos = b.add_vec3(gltf_test::unit_triangle());
    const int uv = b.add_vec2({{0, 0}, {1, 0}, {0, 1}});
    b.push("images", {{"uri", image}});
    b.push("textures", {{"source", 0}});
    b.push("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    b.single_node_scene(b.add_mesh({{"POSITION", pos}, {"TEXCOORD_0", uv}}, 4, -1, 0));
    b.write_data_uri_gltf(path("scene.gltf"));
    return path("scene.gltf");
  }
  std::filesystem::path obj_with_image(const std::string& image) {
    gltf_test::write_text(path("scene.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd " + image + "\n");
    gltf_test::write_text(path("scene.obj"),
                          "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                          "usemtl m\nf 1/1 2/2 3/3\n");
    return path("scene.obj");
  }
  void write_image(const std::string& name, const Bytes& bytes) {
    gltf_test::write_file(path(name), bytes.data(), bytes.size());
  }
  // Loading `scene` must throw SceneError naming it, the image and `word`.
  template <typename Load>
  void expect_error(Load load, const std::filesystem::path& scene, const std::string& image, const std::string& word) {
    try {
      load(scene);
      ADD_FAILURE() << scene << " loaded, expected an error with '" << word << "'";
    } catch (const SceneError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(scene.string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(image), std::string::npos) << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << "expected '" << word << "' in: " << msg;
    }
  }
};

const auto kGltf = [](const std::filesystem::path& p) { return read_gltf(p); };
const auto kObj = [](const std::filesystem::path& p) { return read_obj(p); };

TEST_F(TextureFiles, GltfRefusesMissingCorruptAndTruncatedImages) {
  write_image("good.png", png());
  write_image("good.jpg", jpeg());
  EXPECT_EQ(read_gltf(gltf_with_image("good.png")).images.at(0).width, 8);
  EXPECT_EQ(read_gltf(gltf_with_image("good.jpg")).images.at(0).width, 16);

  expect_error(kGltf, gltf_with_image("absent.png"), "absent.png", "could not be read");
  Bytes corrupt = png();
  corrupt.resize(corrupt.size() / 2);
  corrupt.insert(corrupt.end(), 64, 0xAB);
  write_image("corrupt.png", corrupt);
  expect_error(kGltf, gltf_with_image("corrupt.png"), "image 0", "cannot be decoded");
  write_image("cut.png", cut(png(), png().size() - 20));
  expect_error(kGltf, gltf_with_image("cut.png"), "image 0", "truncated PNG");
  write_image("cut.jpg", cut(jpeg(), jpeg().size() / 2));
  expect_error(kGltf, gltf_with_image("cut.jpg"), "image 0", "no end-of-image marker");
  write_image("no_eoi.jpg", cut(jpeg(), jpeg().size() - 2));
  expect_error(kGltf, gltf_with_image("no_eoi.jpg"), "image 0", "no end-of-image marker");
}

TEST_F(TextureFiles, ObjRefusesMissingCorruptAndTruncatedImages) {
  write_image("good.jpg", jpeg());
  EXPECT_EQ(read_obj(obj_with_image("good.jpg")).images.at(0).width, 16);
  expect_error(kObj, obj_with_image("absent.png"), "texture 'absent.png'", "does not exist");
  write_image("cut.png", cut(png(), png().size() - 5));
  expect_error(kObj, obj_with_image("cut.png"), "texture 'cut.png'", "truncated PNG");
  write_image("cut.jpg", cut(jpeg(), jpeg().size() - 1));
  expect_error(kObj, obj_with_image("cut.jpg"), "texture 'cut.jpg'", "no end-of-image marker");
}

}  // namespace
}  // namespace lancer
