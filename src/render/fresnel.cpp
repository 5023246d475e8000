#include "render/fresnel.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace lancer {

float exact_dielectric_fresnel(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  // Snell: sin_t = sin_i / eta.
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (r_s * r_s + r_p * r_p);
}

float dielectric_f0(float ior) {
  if (!(ior > 0.0f) || !std::isfinite(ior)) return 1.0f;
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

namespace {
// min(f0_ior * colour, 1) for one channel; a negative or NaN product gives 0.
float tinted_f0(float f0_ior, float colour) {
  const float p = f0_ior * colour;
  return p > 0.0f ? std::min(p, 1.0f) : 0.0f;
}
}  // namespace

DielectricFresnel::DielectricFresnel(float ior, const glm::vec3& specular_color, Form form)
    : f0_ior_(dielectric_f0(ior)),
      f0_(tinted_f0(f0_ior_, specular_color.x), tinted_f0(f0_ior_, specular_color.y),
          tinted_f0(f0_ior_, specular_color.z)),
      // The exact shape needs F0 < 1 to be rescaled; F0 = 1 reflects everything either way.
      form_(f0_ior_ < 1.0f ? form : Form::Schlick) {}

float DielectricFresnel::exact_weight(float cos_i, float eta) const {
  return (exact_dielectric_fresnel(cos_i, eta) - f0_ior_) / (1.0f - f0_ior_);
}

}  // namespace lancer
