// How a linear radiance image becomes a picture for people (8-bit sRGB PNG): an exposure
// in stops, then a tone curve, then the sRGB encoding. EXR output never goes through it:
// it stays the renderer's linear radiance.
//
// The curves:
//  - clamp: the identity, clipped to [0, 1]: exact colours up to 1, everything brighter
//    white (what Lancer wrote before; what a test comparing PNG codes wants);
//  - neutral: the Khronos PBR Neutral tone mapper (Khronos 3D Commerce, 2024), made for
//    glTF product renders: below its compression start (0.76) it leaves colours as they
//    are, bar a small toe under 0.08, so base colours keep their hue and value; above it
//    highlights roll off smoothly towards white, desaturating as they go. The default of
//    `lancer render`: a model under a bright environment is not blown out, and a
//    correctly exposed one looks as its material says.
#pragma once

#include <string_view>

#include <glm/vec3.hpp>

namespace lancer {

enum class ToneCurve { Clamp, Neutral };

struct DisplayTransform {
  float exposure_ev = 0.0f;  // the image is multiplied by 2^exposure_ev first
  ToneCurve curve = ToneCurve::Clamp;
};

// Linear radiance -> linear display value in [0, 1] (before the sRGB encoding). NaN and
// negative channels give 0.
glm::vec3 display_map(const glm::vec3& linear, const DisplayTransform& display);

// "clamp" or "neutral"; false for anything else.
bool parse_tone_curve(std::string_view name, ToneCurve& curve);

}  // namespace lancer
