#include "render/bsdf_base_lobes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "render/bsdf_base.h"

namespace lancer {
namespace {

constexpr float kInvPi = std::numbers::inv_pi_v<float>;
// |eta - 1| below this refracts as a delta lobe: the transmitted lobe is then at most
// alpha * 1e-3 radians wide, and the generalised half vector wo + eta wi loses its precision.
constexpr float kIndexMatched = 1e-3f;

// Clamp to [0, 1]; NaN becomes 0.
float unit_clamp(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }
glm::vec3 unit_clamp(const glm::vec3& v) { return {unit_clamp(v.x), unit_clamp(v.y), unit_clamp(v.z)}; }
float average(const glm::vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
glm::vec3 mirror_z(const glm::vec3& v) { return {v.x, v.y, -v.z}; }

// Whether the transmitted base exists at all: a dielectric part that transmits something
// coloured, through an ior light can pass (any ior on a thin wall, which does not refract).
bool transmits(const BaseFresnel& mix, bool thin_walled) {
  return (mix.can_refract() || thin_walled) && (1.0f - mix.metallic()) * mix.transmission() > 0.0f &&
         max_component(mix.base_color()) > 0.0f;
}

// Smith G2(wo, w) with Lambda(wo) from `out` (microfacet.h's formulas).
float smith_g2(const GgxDistribution& ggx, const LobeOutgoing& out, const glm::vec3& w) {
  return 1.0f / (1.0f + out.lambda_o + ggx.lambda(w));
}

}  // namespace

// ---- BaseFresnel -----------------------------------------------------------------------

BaseFresnel::BaseFresnel(const BsdfInputs& in, bool entering)
    : base_color_(unit_clamp(in.base_color)),
      metallic_(unit_clamp(in.metallic)),
      specular_(unit_clamp(in.specular)),
      transmission_(unit_clamp(in.transmission)),
      fresnel_(in.ior, in.specular_color,
               transmission_ > 0.0f ? DielectricFresnel::Form::Exact : DielectricFresnel::Form::Schlick) {
  // A thin wall has air on both sides: light meets the index ior from either side.
  if (can_refract()) fresnel_eta_ = in.thin_walled || entering ? in.ior : 1.0f / in.ior;
}

glm::vec3 BaseFresnel::specular_tint(float cos_wo_h, const glm::vec3& fr) const {
  const glm::vec3 dielectric = (1.0f - metallic_) * specular_ * fr;
  // No metal: skipping its (finite) term adds exactly 0.
  return metallic_ > 0.0f ? metallic_ * schlick_fresnel(base_color_, cos_wo_h) + dielectric : dielectric;
}

float BaseFresnel::base_weight(const glm::vec3& fr) const {
  return (1.0f - metallic_) * (1.0f - specular_ * max_component(fr));
}

bool BaseFresnel::dielectric_reflects() const {
  return (1.0f - metallic_) * specular_ > 0.0f &&
         (fresnel_.form() == DielectricFresnel::Form::Schlick || fresnel_.f0_ior() > 0.0f);
}

// ---- DiffuseLobe -----------------------------------------------------------------------

DiffuseLobe::DiffuseLobe(const BaseFresnel& mix)
    : exists_((1.0f - mix.metallic()) * (1.0f - mix.transmission()) > 0.0f && max_component(mix.base_color()) > 0.0f) {}

LobeValue DiffuseLobe::eval(const BaseFresnel& mix, const glm::vec3& wi, const glm::vec3& fr) const {
  return {(mix.base_weight(fr) * (1.0f - mix.transmission()) * kInvPi * wi.z) * mix.base_color(), kInvPi * wi.z};
}

glm::vec3 DiffuseLobe::sample(glm::vec2 u) {
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
}

// ---- ReflectionLobe --------------------------------------------------------------------

ReflectionLobe::ReflectionLobe(const BaseFresnel& mix, const GgxDistribution& ggx)
    : ggx_(ggx), exists_(mix.metallic() > 0.0f || mix.dielectric_reflects()) {}

float ReflectionLobe::weight(const BaseFresnel& mix, float cos_wo_m, const glm::vec3& fr) const {
  return exists_ ? average(mix.specular_tint(cos_wo_m, fr)) : 0.0f;
}

LobeValue ReflectionLobe::eval(const LobeOutgoing& out, const glm::vec3& wi, const glm::vec3& h,
                               const glm::vec3& tint) const {
  const float d = ggx_.d(h);
  return {tint * (d * smith_g2(ggx_, out, wi) * out.inv_4cos_o), out.g1_o * d * out.inv_4cos_o};
}

glm::vec3 ReflectionLobe::mirror_throughput(const BaseFresnel& mix, const glm::vec3& wo) const {
  return mix.specular_tint(wo.z, mix.reflectance(wo.z));
}

std::optional<glm::vec3> ReflectionLobe::direction(const glm::vec3& wo, const glm::vec3& m) {
  const glm::vec3 wi = reflect_about(wo, m);
  if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface
  return wi;
}

// ---- ThinWallLobe ----------------------------------------------------------------------

ThinWallLobe::ThinWallLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled)
    : ggx_(ggx), exists_(thin_walled && transmits(mix, true)) {}

float ThinWallLobe::weight(const BaseFresnel& mix, const glm::vec3&, const glm::vec3&, const glm::vec3& fr) const {
  return exists_ ? mix.base_weight(fr) * mix.transmission() * mix.base_color_average() : 0.0f;
}

float ThinWallLobe::estimate(const BaseFresnel& mix, const glm::vec3&, float base) const {
  return exists_ ? base * mix.transmission() : 0.0f;
}

std::optional<glm::vec3> ThinWallLobe::facet_normal(const glm::vec3& wo, const glm::vec3& wi) const {
  return reflection_half_vector(wo, mirror_z(wi));
}

// KHR_materials_transmission's thin BTDF: specular_brdf with wi mirrored through the tangent
// plane, H_T = normalize(wo + mirror(wi)); times |cos(wi)| = D G2 / (4 |n.wo|). Its density
// is the reflection density of the mirrored direction (mirroring preserves solid angle).
LobeValue ThinWallLobe::eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi,
                             const glm::vec3& m, const glm::vec3& fr) const {
  const float d = ggx_.d(m);
  const float btdf_cos = d * smith_g2(ggx_, out, mirror_z(wi)) * out.inv_4cos_o;
  return {(mix.base_weight(fr) * mix.transmission() * btdf_cos) * mix.base_color(), out.g1_o * d * out.inv_4cos_o};
}

std::optional<glm::vec3> ThinWallLobe::direction(const glm::vec3& wo, const glm::vec3& m) const {
  const glm::vec3 wi = mirror_z(reflect_about(wo, m));
  if (!(wi.z < 0.0f)) return std::nullopt;  // its mirror image reflected below the surface
  return wi;
}

// ---- RefractionLobe --------------------------------------------------------------------

RefractionLobe::RefractionLobe(const BaseFresnel& mix, const GgxDistribution& ggx, bool thin_walled, float eta)
    : ggx_(ggx),
      eta_(eta),
      exists_(!thin_walled && transmits(mix, false)),
      delta_(ggx.smooth() || std::abs(eta - 1.0f) < kIndexMatched) {}

float RefractionLobe::weight(const BaseFresnel& mix, const glm::vec3& wo, const glm::vec3& m,
                             const glm::vec3& fr) const {
  if (!exists_ || !refract_about(wo, m, eta_)) return 0.0f;
  return mix.base_weight(fr) * mix.transmission() * mix.base_color_average();
}

float RefractionLobe::estimate(const BaseFresnel& mix, const glm::vec3& wo, float base) const {
  if (!exists_ || (delta_ && !refract_about(wo, glm::vec3(0.0f, 0.0f, 1.0f), eta_))) return 0.0f;
  return base * mix.transmission();
}

std::optional<glm::vec3> RefractionLobe::facet_normal(const glm::vec3& wo, const glm::vec3& wi) const {
  return refraction_half_vector(wo, wi, eta_);
}

// Walter et al. 2007, eq. 21 without F, times |cos(wi)|; the density is D_wo(m) times the
// Jacobian |dm / dwi| of refraction (eq. 17).
LobeValue RefractionLobe::eval(const BaseFresnel& mix, const LobeOutgoing& out, const glm::vec3& wi,
                               const glm::vec3& m, const glm::vec3& fr) const {
  const glm::vec3& wo = out.lo;
  const float cos_o = glm::dot(wo, m);
  const float cos_i = glm::dot(wi, m);
  const float denom = cos_o + eta_ * cos_i;
  const float jacobian = eta_ * eta_ * std::abs(cos_i) / (denom * denom);
  const float d = ggx_.d(m);
  const float btdf_cos = cos_o * jacobian * d * smith_g2(ggx_, out, wi) / wo.z;
  return {(mix.base_weight(fr) * mix.transmission() * btdf_cos) * mix.base_color(), ggx_.visible_pdf(wo, m) * jacobian};
}

std::optional<glm::vec3> RefractionLobe::direction(const glm::vec3& wo, const glm::vec3& m) const {
  const std::optional<glm::vec3> wi = refract_about(wo, m, eta_);
  if (!wi || !(wi->z < 0.0f)) return std::nullopt;  // totally reflected, or refracted back up
  return wi;
}

std::optional<glm::vec3> RefractionLobe::delta_direction(const glm::vec3& wo) const {
  return refract_about(wo, glm::vec3(0.0f, 0.0f, 1.0f), eta_);
}

}  // namespace lancer
