// Fresnel terms of the glTF 2.0 metallic-roughness material and its extensions.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace lancer {

// Schlick 1994, as the glTF 2.0 spec (Appendix B.3.4) writes it: F = f0 + (1 - f0) (1 - |V.H|)^5.
// This is the spec's conductor_fresnel weight; the metal's f0 is its base colour.
// Inline: several calls per shading point.
inline float schlick_weight(float cos_theta) {  // (1 - |cos|)^5
  const float m = std::clamp(1.0f - std::abs(cos_theta), 0.0f, 1.0f);
  const float m2 = m * m;
  return m2 * m2 * m;
}
inline glm::vec3 schlick_fresnel(const glm::vec3& f0, float cos_theta) {
  return f0 + (glm::vec3(1.0f) - f0) * schlick_weight(cos_theta);
}

// The exact unpolarised Fresnel reflectance of a smooth dielectric interface (the mean of the
// s and p reflectances); cos_i >= 0 on the incident side, eta = n(transmitted side) /
// n(incident side). 1 under total internal reflection. The Whitted integrator uses it too.
float exact_dielectric_fresnel(float cos_i, float eta);

// F0 of a dielectric with index `ior` against air (KHR_materials_ior): ((ior - 1) / (ior + 1))^2.
// An ior that is not a positive finite number gives 1 (the extension's "ior = 0" convention
// for specular-glossiness conversions: all of the Fresnel range goes to specular colour).
float dielectric_f0(float ior);

// The dielectric Fresnel term `fr` of glTF's fresnel_mix with KHR_materials_ior and
// KHR_materials_specular (its "Implementation" section):
//   f0 = min(dielectric_f0(ior) * specular_color, 1)      (per channel; NaN or < 0 -> 0)
//   fr = f0 + (1 - f0) * w(cos)
// The shape w runs from 0 at normal incidence to 1 at grazing incidence:
// - Schlick: w = (1 - |V.H|)^5, the spec's form, used for opaque materials;
// - Exact: w = (F(cos, eta) - F0) / (1 - F0) with F the exact dielectric reflectance, used
//   when light refracts (KHR_materials_transmission). It reaches 1 at the critical angle, so
//   total internal reflection is kept, and with specular_color = 1 it gives fr = F exactly,
//   so a smooth interface reflects F and transmits 1 - F.
class DielectricFresnel {
 public:
  enum class Form { Schlick, Exact };
  DielectricFresnel(float ior, const glm::vec3& specular_color, Form form);

  // fr at cos_i = |wo.h| >= 0; eta = n(far side) / n(wo side), used by the exact form only.
  glm::vec3 reflectance(float cos_i, float eta) const {
    const float w = form_ == Form::Schlick ? schlick_weight(cos_i) : exact_weight(cos_i, eta);
    // The exact curve dips a hair below F0 near Brewster's angle for large indices; clamping fr
    // (not w) keeps fr = F exactly when specular_color = 1.
    return glm::clamp(f0_ + (glm::vec3(1.0f) - f0_) * w, glm::vec3(0.0f), glm::vec3(1.0f));
  }
  float f0_ior() const { return f0_ior_; }
  Form form() const { return form_; }

 private:
  float exact_weight(float cos_i, float eta) const;  // (F(cos_i, eta) - F0) / (1 - F0)
  float f0_ior_;
  glm::vec3 f0_;
  Form form_;
};

}  // namespace lancer
