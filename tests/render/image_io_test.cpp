// write_image / read_image: round trips, exact sRGB codes, non-finite pixels, and every
// kind of bad path or bad file giving an ImageError that names the file.
#include "render/image_io.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "render/color.h"
#include "temp_dir.h"

namespace lancer {
namespace {

namespace fs = std::filesystem;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

class ImageIoTest : public ::testing::Test {
 protected:
  // A test may leave the folder read-only; TempDir removes it afterwards.
  void TearDown() override {
    std::error_code ignored;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ignored);
  }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  test::TempDir temp_{"lancer_image_io"};
  const fs::path& dir_ = temp_.path();
};

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Runs `action`, which must throw ImageError; returns its message (empty if none).
std::string image_error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const ImageError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an ImageError";
  return {};
}

// A 7x3 image whose every channel differs, so a transposed or flipped read shows.
ImageRGB ramp_image(int width, int height) {
  ImageRGB image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.set(x, y, {0.01f * static_cast<float>(x + 1), 0.1f * static_cast<float>(y + 1), 0.003f * static_cast<float>(x * y)});
  return image;
}

std::uint32_t float_bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// --- OpenEXR ---------------------------------------------------------------------

TEST_F(ImageIoTest, ExrRoundTripIsBitExact) {
  const std::vector<float> values = {0.0f, -0.0f, 1.0f, 0.5f, 1.0f / 3.0f, 3.14159265f, 65504.5f, 1e6f,
                                     3.4e38f, -2.5f, -1e-20f, 1e-30f, std::numeric_limits<float>::min(),
                                     1e-42f, std::numeric_limits<float>::denorm_min(), 7.0f / 255.0f};
  ImageRGB image(7, 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = values[i % values.size()] * (1.0f + static_cast<float>(i / values.size()));
  const fs::path file = dir_ / "exact.exr";
  write_image(image, file);
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 3);
  ASSERT_EQ(back.rgb.size(), image.rgb.size());
  for (std::size_t i = 0; i < image.rgb.size(); ++i) EXPECT_EQ(float_bits(back.rgb[i]), float_bits(image.rgb[i])) << "value " << i;
}

TEST_F(ImageIoTest, ExrKeepsNonFiniteValuesAsTheyAre) {
  ImageRGB image = ramp_image(3, 2);
  image.set(0, 0, {kNaN, 0.5f, 0.5f});
  image.set(2, 1, {kInf, -kInf, kNaN});
  EXPECT_EQ(count_non_finite(image), 2u);
  const fs::path file = dir_ / "nonfinite.exr";
  write_image(image, file);
  const ImageRGB back = read_image(file);
  EXPECT_TRUE(std::isnan(back.at(0, 0).x));
  EXPECT_EQ(back.at(0, 0).y, 0.5f);
  EXPECT_EQ(back.at(2, 1).x, kInf);
  EXPECT_EQ(back.at(2, 1).y, -kInf);
  EXPECT_TRUE(std::isnan(back.at(2, 1).z));
  EXPECT_EQ(count_non_finite(back), 2u);
}

TEST_F(ImageIoTest, ExrReadsHalfRgbaFiles) {
  const fs::path file = dir_ / "half.exr";
  const int width = 5, height = 2;
  std::vector<Imf::Rgba> pixels(static_cast<std::size_t>(width) * height);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = Imf::Rgba(0.5f * static_cast<float>(i), -2.0f, 1024.0f, 0.25f);
  {
    Imf::RgbaOutputFile out(file.c_str(), width, height, Imf::WRITE_RGBA);
    out.setFrameBuffer(pixels.data(), 1, static_cast<std::size_t>(width));
    out.writePixels(height);
  }
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, width);
  ASSERT_EQ(back.height, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      EXPECT_EQ(back.at(x, y), glm::vec3(0.5f * static_cast<float>(y * width + x), -2.0f, 1024.0f)) << x << "," << y;
}

// Writes one FLOAT channel per name, value = base + pixel index, over `window`.
void write_exr_channels(const fs::path& file, const std::vector<std::string>& names, const Imath::Box2i& display,
                        const Imath::Box2i& window) {
  Imf::Header header(display, window);
  const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  std::vector<std::vector<float>> planes(names.size(), std::vector<float>(static_cast<std::size_t>(width) * height));
  Imf::FrameBuffer frame;
  for (std::size_t c = 0; c < names.size(); ++c) {
    for (std::size_t i = 0; i < planes[c].size(); ++i) planes[c][i] = static_cast<float>(10 * c + i);
    header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
    frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, planes[c].data(), window, sizeof(float),
                                            sizeof(float) * static_cast<std::size_t>(width)));
  }
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(height);
}

TEST_F(ImageIoTest, ExrReadsLuminanceOnlyAsGrey) {
  const fs::path file = dir_ / "grey.exr";
  const Imath::Box2i window({0, 0}, {6, 2});
  write_exr_channels(file, {"Y"}, window, window);
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 7; ++x) EXPECT_EQ(back.at(x, y), glm::vec3(static_cast<float>(y * 7 + x))) << x << "," << y;
}

TEST_F(ImageIoTest, ExrDataWindowOffsetFromOriginIsTheImage) {
  const fs::path file = dir_ / "window.exr";
  write_exr_channels(file, {"R", "G", "B", "A"}, Imath::Box2i({0, 0}, {19, 19}), Imath::Box2i({5, 10}, {11, 12}));
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 7; ++x) {
      const float i = static_cast<float>(y * 7 + x);
      EXPECT_EQ(back.at(x, y), glm::vec3(i, 10.0f + i, 20.0f + i)) << x << "," << y;
    }
}

TEST_F(ImageIoTest, ExrWithoutColourChannelsIsRefused) {
  const fs::path file = dir_ / "depth.exr";
  const Imath::Box2i window({0, 0}, {3, 3});
  write_exr_channels(file, {"Z", "R"}, window, window);
  const std::string message = image_error_of([&] { read_image(file); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("channels: R, Z"), std::string::npos) << message;
}

TEST_F(ImageIoTest, ExrWithAbsurdDataWindowIsRefusedBeforeAllocating) {
  const fs::path file = dir_ / "huge.exr";
  write_image(ramp_image(7, 3), file);
  std::string bytes = read_bytes(file);
  // Attribute layout: name\0 type\0 size(int32) then box2i = xMin yMin xMax yMax.
  const std::string key("dataWindow\0box2i\0", 17);
  const std::size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const std::size_t max_x = at + key.size() + 4 + 8;
  for (std::size_t k = 0; k < 8; ++k) bytes[max_x + k] = (k % 4 == 2) ? '\x10' : '\0';  // xMax = yMax = 2^20
  write_bytes(file, bytes);
  const std::string message = image_error_of([&] { read_image(file); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("too large"), std::string::npos) << message;
}

// --- PNG and the other stb formats -------------------------------------------------

TEST_F(ImageIoTest, PngBytesAreTheSrgbCodesOfTheImage) {
  ImageRGB image = ramp_image(7, 3);
  image.set(6, 2, {1.7f, -0.2f, 0.0031308f});
  const fs::path file = dir_ / "ramp.png";
  write_image(image, file);

  int width = 0, height = 0, components = 0;
  stbi_uc* codes = stbi_load(file.c_str(), &width, &height, &components, 3);
  ASSERT_NE(codes, nullptr) << stbi_failure_reason();
  ASSERT_EQ(width, 7);
  ASSERT_EQ(height, 3);
  EXPECT_EQ(components, 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) EXPECT_EQ(codes[i], linear_to_srgb8(image.rgb[i])) << "value " << i;

  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    EXPECT_EQ(back.rgb[i], srgb8_to_linear(codes[i])) << "value " << i;
    EXPECT_EQ(linear_to_srgb8(back.rgb[i]), linear_to_srgb8(image.rgb[i])) << "value " << i;
  }
  stbi_image_free(codes);
}

TEST_F(ImageIoTest, PngKnownCodesAndNonFinitePixels) {
  const std::vector<glm::vec3> pixels = {{0.0f, 1.0f, 0.5f}, {0.0031308f, 0.18f, 0.001f},
                                         {kNaN, kInf, -kInf}, {2.0f, -1.0f, -0.0f}};
  const std::vector<int> expected = {0, 255, 188, 10, 118, 3, 0, 255, 0, 255, 0, 0};
  ImageRGB image(4, 1);
  for (int x = 0; x < 4; ++x) image.set(x, 0, pixels[static_cast<std::size_t>(x)]);
  EXPECT_EQ(count_non_finite(image), 1u);
  const fs::path file = dir_ / "known.png";
  write_image(image, file);
  int width = 0, height = 0, components = 0;
  stbi_uc* codes = stbi_load(file.c_str(), &width, &height, &components, 3);
  ASSERT_NE(codes, nullptr) << stbi_failure_reason();
  ASSERT_EQ(width * height, 4);
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(codes[i], expected[i]) << "value " << i;
  stbi_image_free(codes);
}

TEST_F(ImageIoTest, NonSquareImagesKeepTheirShapeAndOrientation) {
  for (const auto& [width, height] : {std::pair{7, 3}, std::pair{3, 7}, std::pair{2, 5}}) {
    ImageRGB image(width, height);
    image.set(width - 1, 0, {1.0f, 0.0f, 0.0f});  // top right
    image.set(0, height - 1, {0.0f, 0.0f, 1.0f});  // bottom left
    for (const char* ext : {".exr", ".png"}) {
      const fs::path file = dir_ / ("shape_" + std::to_string(width) + "x" + std::to_string(height) + ext);
      write_image(image, file);
      const ImageRGB back = read_image(file);
      ASSERT_EQ(back.width, width) << file;
      ASSERT_EQ(back.height, height) << file;
      EXPECT_EQ(back.at(width - 1, 0), glm::vec3(1.0f, 0.0f, 0.0f)) << file;
      EXPECT_EQ(back.at(0, height - 1), glm::vec3(0.0f, 0.0f, 1.0f)) << file;
      EXPECT_EQ(back.at(0, 0), glm::vec3(0.0f)) << file;
    }
  }
}

TEST_F(ImageIoTest, UppercaseExtensionsAreRecognised) {
  const ImageRGB image = ramp_image(4, 2);
  write_image(image, dir_ / "A.PNG");
  write_image(image, dir_ / "B.Exr");
  EXPECT_EQ(read_image(dir_ / "A.PNG").width, 4);
  EXPECT_EQ(read_image(dir_ / "B.Exr").rgb, image.rgb);
}

TEST_F(ImageIoTest, HdrIsReadAsLinear) {
  const int width = 9, height = 2;  // width >= 8 so stb writes run-length encoded scanlines
  std::vector<float> values(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.25f * static_cast<float>(i % 7) + 100.0f * static_cast<float>(i % 5 == 0);
  const fs::path file = dir_ / "sky.hdr";
  ASSERT_NE(stbi_write_hdr(file.c_str(), width, height, 3, values.data()), 0);
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, width);
  ASSERT_EQ(back.height, height);
  for (std::size_t p = 0; p < values.size(); p += 3) {
    const float largest = std::max({values[p], values[p + 1], values[p + 2]});
    for (std::size_t c = 0; c < 3; ++c)  // RGBE keeps 8 bits relative to the largest channel
      EXPECT_NEAR(back.rgb[p + c], values[p + c], largest / 128.0f) << "value " << p + c;
  }
}

TEST_F(ImageIoTest, JpegIsDecodedFromSrgb) {
  const std::vector<stbi_uc> codes(8 * 8 * 3, 200);
  const fs::path file = dir_ / "flat.JPEG";
  ASSERT_NE(stbi_write_jpg(file.c_str(), 8, 8, 3, codes.data(), 100), 0);
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 8);
  for (float v : back.rgb) EXPECT_NEAR(v, srgb8_to_linear(200), srgb8_to_linear(202) - srgb8_to_linear(200));
}

// --- PNG files built by hand: 16-bit samples and absurd headers --------------------

std::uint32_t crc32_bitwise(const std::string& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : data) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void append_be32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((v >> shift) & 0xFFu));
}

std::string png_chunk(const std::string& type, const std::string& data) {
  std::string chunk;
  append_be32(chunk, static_cast<std::uint32_t>(data.size()));
  chunk += type + data;
  append_be32(chunk, crc32_bitwise(type + data));
  return chunk;
}

// An RGB PNG with the scanlines (filter bytes included) in one stored deflate block.
std::string rgb_png(std::uint32_t width, std::uint32_t height, int bit_depth, const std::string& scanlines) {
  std::string header;
  append_be32(header, width);
  append_be32(header, height);
  header += {static_cast<char>(bit_depth), 2, 0, 0, 0};
  const auto length = static_cast<std::uint16_t>(scanlines.size());
  std::string zlib = {'\x78', '\x01', '\x01', static_cast<char>(length & 0xFF), static_cast<char>(length >> 8),
                      static_cast<char>(~length & 0xFF), static_cast<char>((~length >> 8) & 0xFF)};
  zlib += scanlines;
  std::uint32_t a = 1, b = 0;  // Adler-32 (RFC 1950)
  for (unsigned char byte : scanlines) {
    a = (a + byte) % 65521u;
    b = (b + a) % 65521u;
  }
  append_be32(zlib, (b << 16) | a);
  return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", header) + png_chunk("IDAT", zlib) + png_chunk("IEND", "");
}

TEST_F(ImageIoTest, SixteenBitPngKeepsItsPrecision) {
  // One row, two pixels: (0, 32768, 65535) and (1000, 20000, 60000), big-endian samples.
  const std::vector<std::uint16_t> samples = {0, 32768, 65535, 1000, 20000, 60000};
  std::string scanline(1, '\0');
  for (std::uint16_t s : samples) scanline += {static_cast<char>(s >> 8), static_cast<char>(s & 0xFF)};
  const fs::path file = dir_ / "deep.png";
  write_bytes(file, rgb_png(2, 1, 16, scanline));
  const ImageRGB back = read_image(file);
  ASSERT_EQ(back.width, 2);
  ASSERT_EQ(back.height, 1);
  for (std::size_t i = 0; i < samples.size(); ++i)
    EXPECT_FLOAT_EQ(back.rgb[i], srgb_to_linear(static_cast<float>(samples[i]) / 65535.0f)) << "sample " << i;
}

TEST_F(ImageIoTest, PngWithAbsurdDimensionsIsRefusedBeforeAllocating) {
  // 3e8 pixels: over our 2^28 limit but under stb_image's own 2^30-byte limit.
  const fs::path file = dir_ / "huge.png";
  write_bytes(file, rgb_png(20000, 15000, 8, std::string(4, '\0')));
  const std::string message = image_error_of([&] { read_image(file); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("too large"), std::string::npos) << message;
  // Beyond stb's limit the header is refused by stb itself, still as an ImageError.
  write_bytes(file, rgb_png(65536, 65536, 8, std::string(4, '\0')));
  EXPECT_NE(image_error_of([&] { read_image(file); }).find(file.string()), std::string::npos);
}

// --- Bad paths and bad files -------------------------------------------------------

TEST_F(ImageIoTest, UnknownExtensionsAreRefused) {
  const ImageRGB image = ramp_image(2, 2);
  for (const char* name : {"out.bmp", "out", "out.png.bak", "out.tiff"}) {
    const fs::path file = dir_ / name;
    const std::string message = image_error_of([&] { write_image(image, file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("unknown image extension"), std::string::npos) << message;
  }
  for (const char* name : {"in.jpg", "in.hdr"}) {  // readable but not writable
    const fs::path file = dir_ / name;
    EXPECT_NE(image_error_of([&] { write_image(image, file); }).find(file.string()), std::string::npos);
  }
  write_bytes(dir_ / "in.tga", "not looked at");
  EXPECT_NE(image_error_of([&] { read_image(dir_ / "in.tga"); }).find("unknown image extension"), std::string::npos);
  EXPECT_EQ(listing(), std::vector<std::string>{"in.tga"});  // nothing else was created
}

TEST_F(ImageIoTest, InconsistentImagesAreRefused) {
  ImageRGB empty;
  EXPECT_NE(image_error_of([&] { write_image(empty, dir_ / "empty.png"); }).find("invalid image size"), std::string::npos);
  ImageRGB short_buffer(4, 4);
  short_buffer.rgb.pop_back();
  EXPECT_NE(image_error_of([&] { write_image(short_buffer, dir_ / "short.exr"); }).find("expected width*height*3"),
            std::string::npos);
  ImageRGB huge;  // only the header: the size check must come before any use of rgb
  huge.width = 1 << 15;
  huge.height = 1 << 14;
  EXPECT_NE(image_error_of([&] { write_image(huge, dir_ / "huge.png"); }).find("too large"), std::string::npos);
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageIoTest, WritingIntoMissingDirectoryFailsWithTheOsReason) {
  for (const char* name : {"missing/out.png", "missing/out.exr"}) {
    const fs::path file = dir_ / name;
    const std::string message = image_error_of([&] { write_image(ramp_image(2, 2), file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
  write_bytes(dir_ / "plain", "a file, not a directory");
  const fs::path under_file = dir_ / "plain" / "out.png";
  const std::string message = image_error_of([&] { write_image(ramp_image(2, 2), under_file); });
  EXPECT_NE(message.find(under_file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("Not a directory"), std::string::npos) << message;
  EXPECT_EQ(listing(), std::vector<std::string>{"plain"});
}

TEST_F(ImageIoTest, WritingIntoReadOnlyDirectoryFails) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: directory permissions are not enforced";
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string message = image_error_of([&] { write_image(ramp_image(2, 2), locked / "out.png"); });
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
}

TEST_F(ImageIoTest, AtomicWriteLeavesOnlyTheFinalFile) {
  const fs::path png = dir_ / "frame.png", exr = dir_ / "frame.exr";
  write_bytes(dir_ / "frame.png.tmp", "stale temporary from an interrupted run");
  write_image(ramp_image(3, 3), png);
  write_image(ramp_image(3, 3), exr);
  EXPECT_EQ(listing(), (std::vector<std::string>{"frame.exr", "frame.png"}));
  // Overwriting replaces the content.
  ImageRGB white(3, 3);
  std::fill(white.rgb.begin(), white.rgb.end(), 1.0f);
  write_image(white, png);
  EXPECT_EQ(read_image(png).rgb, std::vector<float>(27, 1.0f));
  EXPECT_EQ(listing(), (std::vector<std::string>{"frame.exr", "frame.png"}));
}

TEST_F(ImageIoTest, FailedRenameRemovesTheTemporary) {
  const fs::path file = dir_ / "taken.exr";
  fs::create_directories(file / "inside");  // a non-empty directory cannot be replaced
  const std::string message = image_error_of([&] { write_image(ramp_image(2, 2), file); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("cannot rename"), std::string::npos) << message;
  EXPECT_EQ(listing(), std::vector<std::string>{"taken.exr"});
}

TEST_F(ImageIoTest, MissingFileNamesTheFile) {
  for (const char* name : {"nope.exr", "nope.png", "nope.hdr"}) {
    const fs::path file = dir_ / name;
    const std::string message = image_error_of([&] { read_image(file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
  fs::create_directories(dir_ / "folder.png");
  EXPECT_NE(image_error_of([&] { read_image(dir_ / "folder.png"); }).find("not a regular file"), std::string::npos);
}

TEST_F(ImageIoTest, CorruptFilesAreRefused) {
  const std::vector<std::string> garbage = {"", "this is not an image at all, just some text",
                                            std::string("\x89PNG\r\n\x1a\n", 8) + "garbage after the signature",
                                            std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + "garbage header",
                                            std::string("\xFF\xD8\xFF\xE0", 4) + "broken jpeg", "#?RADIANCE\nbroken"};
  int n = 0;
  for (const std::string& bytes : garbage)
    for (const char* ext : {".exr", ".png", ".jpg", ".hdr"}) {
      const fs::path file = dir_ / ("corrupt" + std::to_string(n++) + ext);
      write_bytes(file, bytes);
      const std::string message = image_error_of([&] { read_image(file); });
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    }
}

TEST_F(ImageIoTest, DamagedPngDataIsDetectedByItsCrc) {
  const fs::path file = dir_ / "damaged.png";
  write_image(ramp_image(7, 3), file);
  std::string bytes = read_bytes(file);
  const std::size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  bytes[idat + 8] = static_cast<char>(bytes[idat + 8] ^ 0x10);
  write_bytes(file, bytes);
  const std::string message = image_error_of([&] { read_image(file); });
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find("CRC mismatch in chunk IDAT"), std::string::npos) << message;
}

// Every prefix of a valid file (every cut point, not a sample) must be refused.
TEST_F(ImageIoTest, TruncatedFilesAreRefusedAtEveryCut) {
  for (const char* ext : {".exr", ".png"}) {
    const fs::path whole = dir_ / (std::string("whole") + ext);
    write_image(ramp_image(7, 3), whole);
    const std::string bytes = read_bytes(whole);
    ASSERT_GT(bytes.size(), 40u);
    const fs::path cut = dir_ / (std::string("cut") + ext);
    for (std::size_t size = 0; size < bytes.size(); ++size) {
      write_bytes(cut, bytes.substr(0, size));
      const std::string message = image_error_of([&] { read_image(cut); });
      EXPECT_NE(message.find(cut.string()), std::string::npos) << "cut at " << size << ": " << message;
    }
  }
}

}  // namespace
}  // namespace lancer
