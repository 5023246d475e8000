#include "render/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "render/color.h"

namespace lancer {

namespace {

// 8-bit code -> float, built once at start-up so a lookup is a load. sRGB entries come
// from color.h's table (the exact IEC 61966-2-1 curve evaluated in double).
struct DecodeTables {
  std::array<float, 256> linear{};
  std::array<float, 256> srgb{};
};

const DecodeTables kDecode = [] {
  DecodeTables t;
  for (int i = 0; i < 256; ++i) {
    t.linear[std::size_t(i)] = float(i) / 255.0f;
    t.srgb[std::size_t(i)] = srgb8_to_linear(std::uint8_t(i));
  }
  return t;
}();

// Brings a coordinate into one period of its wrap mode before it is scaled to texels,
// so texel indices stay small integers: repeat to [0, 1], mirrored repeat to [0, 2]
// (both exact: x - floor(x) loses no bits here), clamp to [-1, 2], beyond which every
// lookup reads the edge texels anyway.
float reduce(float u, int wrap) {
  if (!std::isfinite(u)) return 0.0f;
  switch (wrap) {
    case kWrapClampToEdge:
      return std::clamp(u, -1.0f, 2.0f);
    case kWrapMirroredRepeat:
      return u - 2.0f * std::floor(0.5f * u);
    default:
      return u - std::floor(u);
  }
}

// Texel index `i` (any int near [0, n)) into [0, n) by the wrap mode. Mirrored repeat
// has period 2n: i and 2n - 1 - i read the same texel, so -1 reads 0 and n reads n - 1.
int wrap_index(int i, int n, int wrap) {
  switch (wrap) {
    case kWrapClampToEdge:
      return std::clamp(i, 0, n - 1);
    case kWrapMirroredRepeat: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    default: {
      const int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

glm::vec4 fetch(const Image& image, int x, int y, TexelEncoding encoding) {
  const std::size_t channels = std::size_t(image.channels);
  const std::uint8_t* p = image.pixels.data() + (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * channels;
  const std::array<float, 256>& colour = encoding == TexelEncoding::Srgb ? kDecode.srgb : kDecode.linear;
  switch (channels) {
    case 1: {
      const float g = colour[p[0]];
      return {g, g, g, 1.0f};
    }
    case 2: {
      const float g = colour[p[0]];
      return {g, g, g, kDecode.linear[p[1]]};
    }
    case 3:
      return {colour[p[0]], colour[p[1]], colour[p[2]], 1.0f};
    default:
      return {colour[p[0]], colour[p[1]], colour[p[2]], kDecode.linear[p[3]]};
  }
}

}  // namespace

TexelFilter texel_filter(const Texture& texture, bool minifying) {
  switch (minifying ? texture.min_filter : texture.mag_filter) {
    case kFilterNearest:
    case 9984:  // NEAREST_MIPMAP_NEAREST
    case 9986:  // NEAREST_MIPMAP_LINEAR
      return TexelFilter::Nearest;
    default:  // LINEAR, LINEAR_MIPMAP_*, or not given
      return TexelFilter::Linear;
  }
}

glm::vec4 sample_image(const Image& image, const Texture& texture, glm::vec2 uv, TexelEncoding encoding,
                       TexelFilter filter) {
  const int w = image.width, h = image.height;
  const float u = reduce(uv.x, texture.wrap_s), v = reduce(uv.y, texture.wrap_t);
  if (filter == TexelFilter::Nearest) {
    // The texel whose square [i, i+1) holds u * w.
    const int x = wrap_index(int(std::floor(u * float(w))), w, texture.wrap_s);
    const int y = wrap_index(int(std::floor(v * float(h))), h, texture.wrap_t);
    return fetch(image, x, y, encoding);
  }
  // Bilinear between the texel centres around (u w - 1/2, v h - 1/2); each texel is
  // decoded (sRGB to linear) before it is weighted, as GPUs filter sRGB textures.
  const float x = u * float(w) - 0.5f, y = v * float(h) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int x0 = wrap_index(int(fx), w, texture.wrap_s), x1 = wrap_index(int(fx) + 1, w, texture.wrap_s);
  const int y0 = wrap_index(int(fy), h, texture.wrap_t), y1 = wrap_index(int(fy) + 1, h, texture.wrap_t);
  const glm::vec4 top = (1.0f - tx) * fetch(image, x0, y0, encoding) + tx * fetch(image, x1, y0, encoding);
  const glm::vec4 bottom = (1.0f - tx) * fetch(image, x0, y1, encoding) + tx * fetch(image, x1, y1, encoding);
  return (1.0f - ty) * top + ty * bottom;
}

glm::vec2 transform_uv(const TextureRef& ref, glm::vec2 uv) { return glm::vec2(ref.transform * glm::vec3(uv, 1.0f)); }

const Image* texture_image(const Scene& scene, const TextureRef& ref) {
  if (!ref.present()) return nullptr;
  const Texture& texture = scene.textures.at(std::size_t(ref.texture));
  if (texture.image < 0) return nullptr;
  return &scene.images.at(std::size_t(texture.image));
}

glm::vec4 sample_texture(const Scene& scene, const TextureRef& ref, glm::vec2 uv0, glm::vec2 uv1,
                         TexelEncoding encoding) {
  const Image* image = texture_image(scene, ref);
  if (!image) return glm::vec4(1.0f);
  const Texture& texture = scene.textures[std::size_t(ref.texture)];
  const glm::vec2 uv = transform_uv(ref, ref.texcoord == 1 ? uv1 : uv0);
  return sample_image(*image, texture, uv, encoding, texel_filter(texture));
}

}  // namespace lancer
