// sRGB transfer functions and luminance.
//
// The curves are the exact piecewise ones of IEC 61966-2-1:1999 (sRGB), section 4.2 /
// 5.2: a linear segment near black joined to a 1/2.4 power law, not a pure gamma of 2.2
// (which differs by up to 2 codes in 8 bits, e.g. linear 0.5 is 188 in sRGB, 186 with
// gamma 2.2). Inputs outside [0, 1] follow the same formulas (negative values stay on
// the linear segment); only the 8-bit encoder clamps.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace lancer {

// sRGB-encoded value in [0, 1] -> linear value.
inline float srgb_to_linear(float encoded) {
  // 0.04045 = 12.92 * 0.0031308: both segments meet there (to 1e-8).
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

// Linear value -> sRGB-encoded value (the opto-electronic transfer function).
inline float linear_to_srgb(float linear) {
  if (linear <= 0.0031308f) return linear * 12.92f;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

// Linear value -> 8-bit sRGB code, clamped to [0, 255] and rounded to nearest.
// NaN maps to 0 and +infinity to 255, so a broken pixel never becomes garbage.
inline std::uint8_t linear_to_srgb8(float linear) {
  if (!(linear > 0.0f)) return 0;  // also catches NaN
  if (linear >= 1.0f) return 255;
  const float code = linear_to_srgb(linear) * 255.0f + 0.5f;
  return static_cast<std::uint8_t>(code >= 255.0f ? 255.0f : code);
}

// 8-bit sRGB code -> linear value, from a table built once (thread-safe static init).
// The table is evaluated in double, so each entry is the nearest float to the exact
// value (the float curve above is a few ulps off near 0.5).
inline float srgb8_to_linear(std::uint8_t code) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double encoded = i / 255.0;
      t[i] = static_cast<float>(encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table[code];
}

// Relative luminance of linear Rec. 709 / sRGB primaries (ITU-R BT.709-6, item 3.3).
inline float luminance(const glm::vec3& rgb) {
  return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z;
}

}  // namespace lancer
