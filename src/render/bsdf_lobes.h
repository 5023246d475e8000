// The layer lobes Bsdf (bsdf.h) stacks on the glTF base (bsdf_base.h). Each is one small
// type with the same four operations, in a local frame whose z axis is the lobe's normal,
// with wo mirrored to wo.z > 0 (the caller mirrors wi with it):
//   eval(wo, wi)    -> BsdfEval: f * |cos(wi)| and the lobe's own sampling density of wi
//   sample(wo, u)   -> wi (nullopt when the drawn direction leaves the lobe's domain)
//   albedo(wo)      -> an estimate of the directional albedo, for choosing among lobes
// A lobe scatters into wo's hemisphere only (both are reflection lobes). No virtual calls:
// Bsdf holds one member of each type.
//
// - ClearcoatLobe (KHR_materials_clearcoat, "Implementation"): the coat is
//     clearcoat_brdf = specular_brdf(clearcoat_normal, alpha = clearcoatRoughness^2)
//   (the GGX D and height-correlated Smith G2 of microfacet.h) and layering with
//     fresnel_coat(n, ior = 1.5, weight, base, layer) = mix(base, layer, weight * fr),
//     fr = 0.04 + 0.96 (1 - |n.V|)^5,
//   i.e. f = base * (1 - clearcoat Fc) + clearcoat Fc clearcoat_brdf. Fc depends on wo only,
//   so the lobe's f is clearcoat Fc D G2 / (4 |n.wo| |n.wi|) and Bsdf scales the base by
//   1 - clearcoat Fc. Sampled by the visible normals (Heitz 2018); below kSmoothAlpha it is a
//   delta (mirror) lobe whose throughput is clearcoat Fc.
// - SheenLobe (KHR_materials_sheen, "Implementation"): sheen_brdf = sheenColor D V with the
//   "Charlie" distribution of Estevez & Kulla 2017, "Production Friendly Microfacet Sheen
//   BRDF", D(m) = (2 + 1/alpha) sin(theta_m)^(1/alpha) / (2 pi), alpha = sheenRoughness^2,
//   and the visibility the extension gives from the same paper,
//   V = 1 / ((1 + Lambda(wo) + Lambda(wi)) 4 |n.wo| |n.wi|) with the paper's fitted
//   Lambda(cos) = exp(L(cos)) below cos 0.5, exp(2 L(0.5) - L(1 - cos)) above,
//   L(x) = a / (1 + b x^c) + d x + e, whose five coefficients are interpolated between the
//   paper's fits at alpha 0 and 1 by (1 - alpha)^2. (The paper's "terminator softening" is
//   not part of the extension and is left out.) Layering: Bsdf scales the base by
//   1 - max(sheenColor) E(|n.wo|), E the lobe's directional albedo for sheenColor 1
//   (sheen_albedo below, tabulated at first use by quadrature of this very lobe).
//   Sampled uniformly over the hemisphere: the lobe is broad and peaks at grazing angles,
//   where a cosine density would vanish.
//   sheenRoughness is clamped to at least kMinSheenRoughness: at 0 the distribution is a
//   delta at grazing facets (1/alpha infinite) that no table or sampler can resolve.
#pragma once

#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf_base.h"
#include "render/microfacet.h"

namespace lancer {

inline constexpr float kClearcoatF0 = 0.04f;         // ior 1.5: ((1.5 - 1) / (1.5 + 1))^2
inline constexpr float kMinSheenRoughness = 0.07f;   // see above

class ClearcoatLobe {
 public:
  ClearcoatLobe() : ggx_(1.0f) {}
  ClearcoatLobe(float weight, float roughness);
  bool exists() const { return weight_ > 0.0f; }
  bool smooth() const { return ggx_.smooth(); }
  // weight * fr(|n.wo|): the coat's share of the layering (KHR_materials_clearcoat fresnel_coat).
  float layer_weight(const glm::vec3& wo) const;
  BsdfEval eval(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<glm::vec3> sample(const glm::vec3& wo, glm::vec2 u) const;
  // layer_weight(wo) times the GGX lobe's albedo at most 1: the Fresnel weight itself.
  float albedo(const glm::vec3& wo) const { return layer_weight(wo); }

 private:
  float weight_ = 0.0f;
  GgxDistribution ggx_;
};

class SheenLobe {
 public:
  SheenLobe() = default;
  SheenLobe(const glm::vec3& color, float roughness);
  bool exists() const { return max_color_ > 0.0f; }
  // 1 - max(sheenColor) E(|n.wo|) clamped to [0, 1]: how much of the base shows through.
  float base_scale(const glm::vec3& wo) const;
  BsdfEval eval(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<glm::vec3> sample(const glm::vec3& wo, glm::vec2 u) const;
  float albedo(const glm::vec3& wo) const;  // average(sheenColor) E(|n.wo|)
  float alpha() const { return alpha_; }

 private:
  glm::vec3 color_{0.0f};
  float max_color_ = 0.0f;
  float roughness_ = 1.0f, alpha_ = 1.0f;
};

// f * |cos(wi)| of the Charlie sheen lobe with sheenColor 1 (wo.z, wi.z > 0, else 0).
float charlie_sheen(const glm::vec3& wo, const glm::vec3& wi, float alpha);
// The Estevez-Kulla Lambda fit at cosine cos_theta in [0, 1].
float charlie_lambda(float cos_theta, float alpha);
// E(cos_o) of charlie_sheen at perceptual roughness `roughness` (clamped to
// [kMinSheenRoughness, 1]): bilinear in a table over (cos_o, roughness) filled at first use
// by sheen_albedo_quadrature.
float sheen_albedo(float cos_o, float roughness);
// The same by direct quadrature (midpoint rule over theta and phi of wi, n x n points).
double sheen_albedo_quadrature(float cos_o, float roughness, int n);

}  // namespace lancer
