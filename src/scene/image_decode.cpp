#include "scene/image_decode.h"

#include <stb_image.h>
#include <webp/decode.h>

#include <climits>
#include <cstdint>
#include <cstring>

#include "scene/scene_error.h"

namespace lancer {

namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};

std::uint32_t big_endian32(const unsigned char* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | std::uint32_t(p[3]);
}

std::string byte_count(std::size_t n) { return std::to_string(n) + (n == 1 ? " byte" : " bytes"); }

std::string png_problem(std::span<const unsigned char> b) {
  std::size_t pos = sizeof(kPngSignature);
  while (pos < b.size()) {
    if (b.size() - pos < 8) return "truncated PNG: the file ends inside a chunk header at byte " + std::to_string(pos);
    const std::uint32_t length = big_endian32(&b[pos]);
    const std::string type(reinterpret_cast<const char*>(&b[pos + 4]), 4);
    if (length > 0x7FFFFFFFu) return "corrupt PNG: chunk at byte " + std::to_string(pos) + " has an invalid length";
    const std::size_t whole = 12 + std::size_t(length);  // length, type, data, CRC
    if (b.size() - pos < whole)
      return "truncated PNG: chunk '" + type + "' at byte " + std::to_string(pos) + " needs " + byte_count(whole) +
             " but the file ends after " + byte_count(b.size() - pos);
    if (type == "IEND") return "";
    pos += whole;
  }
  return "truncated PNG: the file ends without an IEND chunk";
}

// Markers without a length field (ITU-T T.81, table B.1): RSTn, SOI, EOI, TEM.
bool standalone_marker(unsigned char m) { return (m >= 0xD0 && m <= 0xD8) || m == 0x01; }

std::string jpeg_problem(std::span<const unsigned char> b) {
  const std::string missing_eoi = "truncated JPEG: no end-of-image marker (0xFFD9)";
  std::size_t pos = 2;  // after SOI
  while (true) {
    // Find the next marker; libjpeg likewise skips stray bytes before one.
    while (pos < b.size() && b[pos] != 0xFF) ++pos;
    while (pos < b.size() && b[pos] == 0xFF) ++pos;  // 0xFF fill bytes
    if (pos >= b.size()) return missing_eoi + ": the file ends between segments";
    const unsigned char marker = b[pos++];
    if (marker == 0xD9) return "";
    if (marker == 0x00 || standalone_marker(marker)) continue;
    if (b.size() - pos < 2) return missing_eoi + ": the file ends inside a segment header";
    const std::size_t length = std::size_t(b[pos]) << 8 | b[pos + 1];
    if (length < 2) return "corrupt JPEG: segment at byte " + std::to_string(pos - 2) + " has length " +
                           std::to_string(length);
    if (b.size() - pos < length) return missing_eoi + ": the file ends inside a segment";
    pos += length;
    if (marker != 0xDA) continue;  // not SOS
    // Entropy-coded data: 0xFF 0x00 is a stuffed 0xFF and 0xFF 0xD0..0xD7 a restart
    // marker, both part of the scan; any other 0xFF xx is the next marker.
    while (true) {
      while (pos < b.size() && b[pos] != 0xFF) ++pos;
      if (b.size() - pos < 2) return missing_eoi + ": the file ends inside the image data";
      const unsigned char next = b[pos + 1];
      if (next == 0x00 || (next >= 0xD0 && next <= 0xD7)) {
        pos += 2;
      } else if (next == 0xFF) {
        ++pos;  // fill byte before a marker
      } else {
        break;  // the outer loop reads this marker
      }
    }
  }
}

// RIFF container with form type WEBP (WebP container specification, "RIFF Header").
bool is_webp(std::span<const unsigned char> b) {
  return b.size() >= 12 && std::memcmp(b.data(), "RIFF", 4) == 0 && std::memcmp(b.data() + 8, "WEBP", 4) == 0;
}

std::string webp_status(VP8StatusCode status) {
  switch (status) {
    case VP8_STATUS_NOT_ENOUGH_DATA:
      return "truncated WebP: the data ends before the image does";
    case VP8_STATUS_BITSTREAM_ERROR:
      return "corrupt WebP data";
    case VP8_STATUS_UNSUPPORTED_FEATURE:
      return "a WebP feature libwebp does not support";
    case VP8_STATUS_OUT_OF_MEMORY:
      return "out of memory decoding WebP";
    default:
      return "WebP decoder status " + std::to_string(int(status));
  }
}

// libwebp decodes. It refuses truncated data itself (VP8_STATUS_NOT_ENOUGH_DATA, checked
// for lossy and lossless files cut anywhere), so no container walk is needed as for
// JPEG. It allocates its own output, which stays untouched until rows decode: a header
// claiming 16383 x 16383 texels followed by garbage costs no memory. The pixels are
// copied out once the whole image decoded.
Image decode_webp(std::span<const unsigned char> bytes, std::string name, const std::string& file,
                  const std::string& what) {
  WebPDecoderConfig config;
  if (!WebPInitDecoderConfig(&config)) throw SceneError(file, what + " cannot be decoded: libwebp version mismatch");
  VP8StatusCode status = WebPGetFeatures(bytes.data(), bytes.size(), &config.input);
  if (status != VP8_STATUS_OK) throw SceneError(file, what + " cannot be decoded: " + webp_status(status));
  const int width = config.input.width, height = config.input.height;
  if (config.input.has_animation) throw SceneError(file, what + " is an animated WebP, which is not supported");
  if (width <= 0 || height <= 0 || (long long)width * height > kMaxImagePixels)
    throw SceneError(file, what + " has unsupported size " + std::to_string(width) + "x" + std::to_string(height));
  const int channels = config.input.has_alpha ? 4 : 3;
  config.output.colorspace = channels == 4 ? MODE_RGBA : MODE_RGB;
  status = WebPDecode(bytes.data(), bytes.size(), &config);
  if (status != VP8_STATUS_OK) {
    WebPFreeDecBuffer(&config.output);
    throw SceneError(file, what + " cannot be decoded: " + webp_status(status));
  }
  Image out;
  out.name = std::move(name);
  out.width = width;
  out.height = height;
  out.channels = channels;
  const WebPRGBABuffer& rgba = config.output.u.RGBA;
  const std::size_t row = std::size_t(width) * std::size_t(channels);
  out.pixels.resize(row * std::size_t(height));
  for (int y = 0; y < height; ++y)
    std::memcpy(out.pixels.data() + std::size_t(y) * row, rgba.rgba + std::size_t(y) * std::size_t(rgba.stride), row);
  WebPFreeDecBuffer(&config.output);
  return out;
}

}  // namespace

std::string truncation_problem(std::span<const unsigned char> bytes) {
  if (bytes.size() >= sizeof(kPngSignature) && std::memcmp(bytes.data(), kPngSignature, sizeof(kPngSignature)) == 0)
    return png_problem(bytes);
  if (bytes.size() >= 2 && bytes[0] == 0xFF && bytes[1] == 0xD8) return jpeg_problem(bytes);
  return "";
}

Image decode_image(std::span<const unsigned char> bytes, std::string name, const std::string& file,
                   const std::string& what) {
  if (bytes.empty()) throw SceneError(file, what + " cannot be decoded: no data");
  if (bytes.size() > std::size_t(INT_MAX)) throw SceneError(file, what + " is too large to decode (over 2 GiB)");
  if (is_webp(bytes)) return decode_webp(bytes, std::move(name), file, what);
  const int length = int(bytes.size());
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), length, &width, &height, &channels))
    throw SceneError(file, what + " cannot be decoded: " + std::string(stbi_failure_reason()));
  if (width <= 0 || height <= 0 || (long long)width * height > kMaxImagePixels)
    throw SceneError(file, what + " has unsupported size " + std::to_string(width) + "x" + std::to_string(height));
  if (const std::string problem = truncation_problem(bytes); !problem.empty())
    throw SceneError(file, what + " cannot be decoded: " + problem);
  stbi_uc* pixels = stbi_load_from_memory(bytes.data(), length, &width, &height, &channels, 0);
  if (!pixels) throw SceneError(file, what + " cannot be decoded: " + std::string(stbi_failure_reason()));
  Image out;
  out.name = std::move(name);
  out.width = width;
  out.height = height;
  out.channels = channels;
  out.pixels.assign(pixels, pixels + std::size_t(width) * std::size_t(height) * std::size_t(channels));
  stbi_image_free(pixels);
  return out;
}

}  // namespace lancer
