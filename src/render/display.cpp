#include "render/display.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace lancer {

namespace {

// Khronos PBR Neutral, as its specification defines it: subtract a small offset (a
// quadratic toe below 0.08, else 0.04), and when the brightest channel passes the start
// of compression, scale the colour so that channel follows 1 - d^2 / (peak + d - start)
// and blend towards grey of the new peak by 1 - 1 / (desaturation (peak - new) + 1).
glm::vec3 pbr_neutral(glm::vec3 c) {
  constexpr float kStart = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  const float x = std::min({c.r, c.g, c.b});
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  c -= offset;
  const float peak = std::max({c.r, c.g, c.b});
  if (peak < kStart) return c;
  constexpr float d = 1.0f - kStart;
  const float new_peak = 1.0f - d * d / (peak + d - kStart);
  c *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  return glm::mix(c, glm::vec3(new_peak), g);
}

float non_negative(float v) { return v > 0.0f ? v : 0.0f; }  // NaN too

}  // namespace

glm::vec3 display_map(const glm::vec3& linear, const DisplayTransform& display) {
  const float scale = std::exp2(display.exposure_ev);
  glm::vec3 c(non_negative(linear.r), non_negative(linear.g), non_negative(linear.b));
  c *= scale;
  if (display.curve == ToneCurve::Neutral) {
    // Infinity would make the curve's arithmetic NaN; anything that bright is white.
    if (!std::isfinite(c.r + c.g + c.b)) return glm::vec3(1.0f);
    c = pbr_neutral(c);
  }
  return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
}

bool parse_tone_curve(std::string_view name, ToneCurve& curve) {
  if (name == "clamp") {
    curve = ToneCurve::Clamp;
    return true;
  }
  if (name == "neutral") {
    curve = ToneCurve::Neutral;
    return true;
  }
  return false;
}

}  // namespace lancer
