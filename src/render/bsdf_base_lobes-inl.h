// Inline definitions for bsdf_base_lobes.h: each lobe's per-direction work, which BaseBsdf
// calls for every light sample and BSDF sample (out of line, each is a call across files).
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>

namespace lancer {
namespace base_lobes {

inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline float average(const glm::vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
inline float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline glm::vec3 mirror_z(const glm::vec3& v) { return {v.x, v.y, -v.z}; }
// Smith G2(wo, w) with Lambda(wo) from `out` (microfacet.h's formulas).
inline float smith_g2(const GgxDistribution& ggx, const LobeOutgoing& out, const glm::vec3& w) {
  return 1.0f / (1.0f + out.lambda_o + ggx.lambda(w));
}

}  // namespace base_lobes

inline glm::vec3 BaseFresnel::specular_tint(float cos_wo_h, const glm::vec3& fr) const {
  const glm::vec3 dielectric = (1.0f - metallic_) * specular_ * fr;
  // No metal: skipping its (finite) term adds exactly 0.
  return metallic_ > 0.0f ? metallic_ * schlick_fresnel(base_color_, cos_wo_h) + dielectric : dielectric;
}

inline float BaseFresnel::base_weight(const glm::vec3& fr) const {
  return (1.0f - metallic_) * (1.0f - specular_ * base_lobes::max_component(fr));
}

inline LobeValue DiffuseLobe::eval(const BaseFresnel& mix, const glm::vec3& wi, const glm::vec3& fr) const {
  return {(mix.base_weight(fr) * (1.0f - mix.transmission()) * base_lobes::kInvPi * wi.z) * mix.base_color(),
          base_lobes::kInvPi * wi.z};
}

inline float ReflectionLobe::weight(const BaseFresnel& mix, float cos_wo_m, const glm::vec3& fr) const {
  return exists_ ? base_lobes::average(mix.specular_tint(cos_wo_m, fr)) : 0.0f;
}

// With k = a^2 s.z^2 + s.x^2 + s.y^2 = |s|^2 ((n.h)^2 (a^2 - 1) + 1), D = a^2 |s|^4 / (pi k^2);
// with r = sqrt(wi.z^2 + a^2 (wi.x^2 + wi.y^2)), Lambda(wi) = (r / wi.z - 1) / 2, so
// G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) = 2 wi.z / g, g = wi.z (1 + 2 Lambda(wo)) + r.
// One division then gives both D / g and, times g, D: the value and the density share it.
inline LobeValue ReflectionLobe::eval(const LobeOutgoing& out, const glm::vec3& wi, const HalfVectorSum& h,
                                      const glm::vec3& tint) const {
  const float a2 = ggx_.alpha() * ggx_.alpha();
  const float k = a2 * h.s.z * h.s.z + (h.s.x * h.s.x + h.s.y * h.s.y);
  const float r = std::sqrt(wi.z * wi.z + a2 * (wi.x * wi.x + wi.y * wi.y));
  const float g = wi.z * (1.0f + 2.0f * out.lambda_o) + r;
  // Lambda(wo) infinite (wo in the tangent plane up to a subnormal): G1 and G2 are 0.
  if (!(g <= std::numeric_limits<float>::max())) return {};
  const float d_num = a2 * h.len2 * h.len2, d_den = std::numbers::pi_v<float> * k * k;
  // Where wo grazes to within about 1e-30, g is so large that d_den g would overflow: two
  // divisions there.
  const float d_over_g = g < 0x1p100f ? d_num / (d_den * g) : d_num / d_den / g;
  return {tint * (d_over_g * (2.0f * wi.z) * out.inv_4cos_o), out.g1_o * (d_over_g * g) * out.inv_4cos_o};
}

inline std::optional<glm::vec3> ReflectionLobe::direction(const glm::vec3& wo, const glm::vec3& m) {
  const glm::vec3 wi = reflect_about(wo, m);
  if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface
  return wi;
}

inline float ThinWallLobe::weight(const BaseFresnel& mix, const glm::vec3&, const glm::vec3&,
                                  const glm::vec3& fr) const {
  return exists_ ? mix.base_weight(fr) * mix.transmission() * mix.base_color_average() : 0.0f;
}

inline float ThinWallLobe::estimate(const BaseFresnel& mix, const glm::vec3&, float base) const {
  return exists_ ? base * mix.transmission() : 0.0f;
}

inline std::optional<glm::vec3> ThinWallLobe::facet_normal(const glm::vec3& wo, const glm::vec3& wi) const {
  return reflection_half_vector(wo, base_lobes::mirror_z(wi));
}

// KHR_materials_transmission's thin BTDF: specular_brdf with wi mirrored through the tangent
// plane, H_T = normalize(wo + mirror(wi)); times |cos(wi)| = D G2 / (4 |n.wo|). Its density
// is the reflection density of the mirrored direction (mirroring preserves solid angle).
inline LobeValue ThinWallLobe::eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi,
                                    const glm::vec3& m, const glm::vec3& fr) const {
  const float d = ggx_.d(m);
  const float btdf_cos = d * base_lobes::smith_g2(ggx_, out, base_lobes::mirror_z(wi)) * out.inv_4cos_o;
  return {(mix.base_weight(fr) * mix.transmission() * btdf_cos) * mix.base_color(), out.g1_o * d * out.inv_4cos_o};
}

inline std::optional<glm::vec3> ThinWallLobe::direction(const glm::vec3& wo, const glm::vec3& m) const {
  const glm::vec3 wi = base_lobes::mirror_z(reflect_about(wo, m));
  if (!(wi.z < 0.0f)) return std::nullopt;  // its mirror image reflected below the surface
  return wi;
}

inline float RefractionLobe::weight(const BaseFresnel& mix, const glm::vec3& wo, const glm::vec3& m,
                                    const glm::vec3& fr) const {
  if (!exists_ || !refract_about(wo, m, eta_)) return 0.0f;
  return mix.base_weight(fr) * mix.transmission() * mix.base_color_average();
}

inline float RefractionLobe::estimate(const BaseFresnel& mix, const glm::vec3& wo, float base) const {
  if (!exists_ || (delta_ && !refract_about(wo, glm::vec3(0.0f, 0.0f, 1.0f), eta_))) return 0.0f;
  return base * mix.transmission();
}

inline std::optional<glm::vec3> RefractionLobe::facet_normal(const glm::vec3& wo, const glm::vec3& wi) const {
  return refraction_half_vector(wo, wi, eta_);
}

// Walter et al. 2007, eq. 21 without F, times |cos(wi)|; the density is D_wo(m) times the
// Jacobian |dm / dwi| of refraction (eq. 17).
inline LobeValue RefractionLobe::eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi,
                                      const glm::vec3& m, const glm::vec3& fr) const {
  const glm::vec3& wo = out.lo;
  const float cos_o = glm::dot(wo, m);
  const float cos_i = glm::dot(wi, m);
  const float denom = cos_o + eta_ * cos_i;
  const float jacobian = eta_ * eta_ * std::abs(cos_i) / (denom * denom);
  const float d = ggx_.d(m);
  const float btdf_cos = cos_o * jacobian * d * base_lobes::smith_g2(ggx_, out, wi) / wo.z;
  return {(mix.base_weight(fr) * mix.transmission() * btdf_cos) * mix.base_color(), ggx_.visible_pdf(wo, m) * jacobian};
}

inline std::optional<glm::vec3> RefractionLobe::direction(const glm::vec3& wo, const glm::vec3& m) const {
  const std::optional<glm::vec3> wi = refract_about(wo, m, eta_);
  if (!wi || !(wi->z < 0.0f)) return std::nullopt;  // totally reflected, or refracted back up
  return wi;
}

inline std::optional<glm::vec3> RefractionLobe::delta_direction(const glm::vec3& wo) const {
  return refract_about(wo, glm::vec3(0.0f, 0.0f, 1.0f), eta_);
}

}  // namespace lancer
