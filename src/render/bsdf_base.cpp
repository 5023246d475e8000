#include "render/bsdf_base.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace lancer {
namespace {

constexpr float kInvPi = std::numbers::inv_pi_v<float>;
// |eta - 1| below this refracts as a delta lobe: the transmitted lobe is then at most
// alpha * 1e-3 radians wide, and the generalised half vector wo + eta wi loses its precision.
constexpr float kIndexMatched = 1e-3f;
// Smallest selection weight of a non-delta lobe that exists. The albedo estimates are taken
// at wo only and can be 0 where the lobe is not (a black metal at normal incidence); the
// floor keeps every direction the lobe reaches sampled.
constexpr float kMinLobeEstimate = 0.02f;

// Clamp to [0, 1]; NaN becomes 0.
float unit_clamp(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }
glm::vec3 unit_clamp(const glm::vec3& v) { return {unit_clamp(v.x), unit_clamp(v.y), unit_clamp(v.z)}; }
float average(const glm::vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
float max_component(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

glm::vec3 sample_cosine_hemisphere(glm::vec2 u) {
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
}

glm::vec3 mirror_z(const glm::vec3& v) { return {v.x, v.y, -v.z}; }

// normalize(a + b) for two unit directions above the surface (a.z, b.z > 0), also where
// they are nearly opposite and grazing: their sum's squared length then underflows, and
// glm::normalize would give NaN; the sum is rescaled first (exactly, by a power of two).
glm::vec3 half_vector(const glm::vec3& a, const glm::vec3& b) {
  glm::vec3 sum = a + b;
  float len2 = glm::dot(sum, sum);
  if (!(len2 >= std::numeric_limits<float>::min())) {
    sum *= 0x1p60f;
    len2 = glm::dot(sum, sum);
  }
  return sum * (1.0f / std::sqrt(len2));
}

}  // namespace

// ---- ShadingFrame ----------------------------------------------------------------------

ShadingFrame ShadingFrame::from_normal(const glm::vec3& n) {
  // Duff et al. 2017: a branchless basis, continuous except where n.z changes sign.
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), glm::vec3(b, sign + n.y * n.y * a, -n.y), n};
}

ShadingFrame ShadingFrame::from_normal_tangent(const glm::vec3& n, const glm::vec3& t) {
  const glm::vec3 projected = t - n * glm::dot(n, t);
  const float len = glm::length(projected);
  if (!(len > 1e-6f * glm::length(t)) || !std::isfinite(len)) return from_normal(n);
  const glm::vec3 tangent = projected / len;
  return {tangent, glm::cross(n, tangent), n};
}

ShadingFrame ShadingFrame::from_orthonormal(const glm::vec3& n, const glm::vec3& t) {
  return {t, glm::cross(n, t), n};
}

glm::vec3 ShadingFrame::to_local(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }

glm::vec3 ShadingFrame::to_world(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }

// ---- Bsdf ------------------------------------------------------------------------------

BaseBsdf::BaseBsdf(const BsdfInputs& in, const ShadingFrame& frame, bool entering)
    : frame_(frame),
      base_color_(unit_clamp(in.base_color)),
      metallic_(unit_clamp(in.metallic)),
      specular_(unit_clamp(in.specular)),
      transmission_(unit_clamp(in.transmission)),
      ggx_(unit_clamp(in.roughness) * unit_clamp(in.roughness)),
      fresnel_(in.ior, in.specular_color,
               unit_clamp(in.transmission) > 0.0f ? DielectricFresnel::Form::Exact : DielectricFresnel::Form::Schlick),
      eta_(1.0f),
      fresnel_eta_(1.0f),
      entering_(entering),
      thin_walled_(in.thin_walled) {
  // dielectric_f0 < 1 exactly when ior is a usable index of refraction.
  const bool can_refract = fresnel_.f0_ior() < 1.0f;
  if (can_refract) {
    // A thin wall has air on both sides: light meets the index ior from either side, and
    // leaves into air again, unbent.
    fresnel_eta_ = thin_walled_ || entering ? in.ior : 1.0f / in.ior;
    eta_ = thin_walled_ ? 1.0f : fresnel_eta_;
  }
  const float dielectric = 1.0f - metallic_;
  const bool dielectric_reflects =
      dielectric * specular_ > 0.0f &&
      (fresnel_.form() == DielectricFresnel::Form::Schlick || fresnel_.f0_ior() > 0.0f);
  const bool tinted = max_component(base_color_) > 0.0f;
  has_reflection_ = metallic_ > 0.0f || dielectric_reflects;
  has_diffuse_ = dielectric * (1.0f - transmission_) > 0.0f && tinted;
  has_transmission_ = (can_refract || thin_walled_) && dielectric * transmission_ > 0.0f && tinted;
  // The thin-walled lobe is the reflection lobe mirrored: exactly as smooth as it.
  smooth_transmission_ = ggx_.smooth() || (!thin_walled_ && std::abs(eta_ - 1.0f) < kIndexMatched);
  split_at_normal_ = ggx_.smooth() || (has_transmission_ && smooth_transmission_);
}

bool BaseBsdf::has_delta() const {
  return (has_reflection_ && ggx_.smooth()) || (has_transmission_ && smooth_transmission_);
}

bool BaseBsdf::is_delta_only() const {
  return has_delta() && !has_diffuse_ && (!has_reflection_ || ggx_.smooth()) &&
         (!has_transmission_ || smooth_transmission_);
}

// The colour that multiplies specular_brdf: metal's conductor_fresnel and the dielectric's
// specular * fr, mixed by metallic (spec B.2, KHR_materials_specular).
inline glm::vec3 BaseBsdf::specular_tint(float cos_wo_h, const glm::vec3& fr) const {
  const glm::vec3 dielectric = (1.0f - metallic_) * specular_ * fr;
  // No metal: skipping its (finite) term adds exactly 0.
  return metallic_ > 0.0f ? metallic_ * schlick_fresnel(base_color_, cos_wo_h) + dielectric : dielectric;
}

// Weight of the dielectric's base (diffuse + transmission): (1 - metallic)(1 - specular max(fr)).
inline float BaseBsdf::base_weight(const glm::vec3& fr) const {
  return (1.0f - metallic_) * (1.0f - specular_ * max_component(fr));
}

BaseBsdf::Outgoing BaseBsdf::outgoing(const glm::vec3& wo) const {
  Outgoing out;
  out.wo = wo;
  out.lo = frame_.to_local(wo);
  if (!(out.lo.z != 0.0f)) return out;  // in the tangent plane, or NaN
  out.valid = true;
  out.flipped = out.lo.z < 0.0f;
  if (out.flipped) out.lo = mirror_z(out.lo);
  if (!ggx_.smooth()) {
    out.lambda_o = ggx_.lambda(out.lo);
    out.g1_o = 1.0f / (1.0f + out.lambda_o);
  }
  // Clamped at the smallest normal float: for a subnormal lo.z, Lambda(lo) is infinite and
  // G1, G2 are 0, and 0 times a finite factor stays 0 (an infinite one would give NaN).
  out.inv_4cos_o = 1.0f / (4.0f * std::max(out.lo.z, std::numeric_limits<float>::min()));
  out.lobes = choose_lobes(out.lo);
  return out;
}

inline glm::vec3 BaseBsdf::to_oriented_local(const Outgoing& out, const glm::vec3& wi) const {
  const glm::vec3 li = frame_.to_local(wi);
  return out.flipped ? mirror_z(li) : li;
}

BaseBsdf::InterfaceSplit BaseBsdf::interface_split(const glm::vec3& wo, const glm::vec3& m) const {
  const float cos_wo_m = glm::dot(wo, m);
  return interface_split(wo, m, cos_wo_m, fresnel_.reflectance(cos_wo_m, fresnel_eta_));
}

inline BaseBsdf::InterfaceSplit BaseBsdf::interface_split(const glm::vec3& wo, const glm::vec3& m, float cos_wo_m,
                                           const glm::vec3& fr) const {
  const float r = has_reflection_ ? average(specular_tint(cos_wo_m, fr)) : 0.0f;
  const bool passes = thin_walled_ || refract_about(wo, m, eta_).has_value();  // no TIR on a thin wall
  const float t = has_transmission_ && passes ? base_weight(fr) * transmission_ * average(base_color_) : 0.0f;
  const float sum = r + t;
  if (!(sum > 0.0f)) return {};
  return {r / sum, t / sum};
}

BaseBsdf::LobeChoice BaseBsdf::choose_lobes(const glm::vec3& wo) const {
  // Albedo estimates with the facet normal replaced by n: exact for the delta lobes.
  const glm::vec3 fr = fresnel_.reflectance(wo.z, fresnel_eta_);
  const float base = base_weight(fr) * average(base_color_);
  float interface = 0.0f, diffuse = 0.0f;
  if (has_reflection_) interface += average(specular_tint(wo.z, fr));
  if (has_transmission_ &&
      (thin_walled_ || !smooth_transmission_ || refract_about(wo, glm::vec3(0.0f, 0.0f, 1.0f), eta_)))
    interface += base * transmission_;
  const bool rough_interface = (has_reflection_ && !ggx_.smooth()) || (has_transmission_ && !smooth_transmission_);
  if (rough_interface) interface = std::max(interface, kMinLobeEstimate);
  if (has_diffuse_) diffuse = std::max(base * (1.0f - transmission_), kMinLobeEstimate);
  const float sum = interface + diffuse;
  if (!(sum > 0.0f)) return {};
  return {interface / sum, diffuse / sum, sum};
}

// f * |cos(wi)| and the sampling density together: the two share the half vector, its
// Fresnel factor and D. `lobes` is only read for the density.
BsdfEval BaseBsdf::eval_local(const Outgoing& out, const glm::vec3& wi) const {
  const glm::vec3& wo = out.lo;
  const LobeChoice& lobes = out.lobes;
  // Smith G2(wo, w) with Lambda(wo) from `out` (microfacet.h's formulas).
  const auto g2 = [&](const glm::vec3& w) { return 1.0f / (1.0f + out.lambda_o + ggx_.lambda(w)); };
  BsdfEval e;
  if (wi.z > 0.0f) {
    const bool rough_reflection = has_reflection_ && !ggx_.smooth();
    if (!has_diffuse_ && !rough_reflection) return e;
    const glm::vec3 h = half_vector(wo, wi);
    const float cos_wo_h = glm::dot(wo, h);
    const glm::vec3 fr = fresnel_.reflectance(cos_wo_h, fresnel_eta_);
    if (rough_reflection) {
      const float d = ggx_.d(h);
      // specular_brdf * cos(wi) = D G2 / (4 |n.wo|)
      const glm::vec3 tint = specular_tint(cos_wo_h, fr);
      e.f += tint * (d * g2(wi) * out.inv_4cos_o);
      if (lobes.interface > 0.0f) {
        // D_wo(h) / (4 wo.h) with D_wo(h) = G1(wo) (wo.h) D(h) / wo.z (Heitz 2018), times the
        // probability of reflecting rather than refracting: without transmission,
        // interface_split's r / (r + 0), which is 1 for any r > 0.
        const float reflect = split_at_normal_     ? interface_split(wo, glm::vec3(0.0f, 0.0f, 1.0f)).reflect
                              : !has_transmission_ ? (average(tint) > 0.0f ? 1.0f : 0.0f)
                                                   : interface_split(wo, h, cos_wo_h, fr).reflect;
        e.pdf += lobes.interface * reflect * out.g1_o * d * out.inv_4cos_o;
      }
    }
    if (has_diffuse_) {
      e.f += (base_weight(fr) * (1.0f - transmission_) * kInvPi * wi.z) * base_color_;
      e.pdf += lobes.diffuse * kInvPi * wi.z;
    }
  } else if (wi.z < 0.0f && has_transmission_ && !smooth_transmission_ && thin_walled_) {
    // KHR_materials_transmission's thin BTDF: specular_brdf with wi mirrored through the
    // tangent plane, H_T = normalize(wo + mirror(wi)); times |cos(wi)| = D G2 / (4 |n.wo|).
    // Its density is the reflection density of the mirrored direction (mirroring preserves
    // solid angle).
    const glm::vec3 wr = mirror_z(wi);
    const glm::vec3 h = half_vector(wo, wr);
    const float cos_wo_h = glm::dot(wo, h);
    const glm::vec3 fr = fresnel_.reflectance(cos_wo_h, fresnel_eta_);
    const float d = ggx_.d(h);
    const float btdf_cos = d * g2(wr) * out.inv_4cos_o;
    e.f += (base_weight(fr) * transmission_ * btdf_cos) * base_color_;
    if (lobes.interface > 0.0f)
      e.pdf += lobes.interface * interface_split(wo, h, cos_wo_h, fr).refract * out.g1_o * d * out.inv_4cos_o;
  } else if (wi.z < 0.0f && has_transmission_ && !smooth_transmission_) {
    const auto h = refraction_half_vector(wo, wi, eta_);
    if (!h) return e;
    const float cos_o = glm::dot(wo, *h);
    const float cos_i = glm::dot(wi, *h);
    const float denom = cos_o + eta_ * cos_i;
    // Walter et al. 2007, eq. 21 without F, times |cos(wi)|.
    const float d = ggx_.d(*h);
    const float btdf_cos = eta_ * eta_ * cos_o * std::abs(cos_i) * d * g2(wi) / (wo.z * denom * denom);
    const glm::vec3 fr = fresnel_.reflectance(cos_o, fresnel_eta_);
    e.f += (base_weight(fr) * transmission_ * btdf_cos) * base_color_;
    if (lobes.interface > 0.0f) {
      // D_wo(h) times the Jacobian |dh / dwi| of refraction (Walter et al. 2007, eq. 17).
      const float refract = interface_split(wo, *h, cos_o, fr).refract;
      e.pdf += lobes.interface * refract * ggx_.visible_pdf(wo, *h) * eta_ * eta_ * std::abs(cos_i) / (denom * denom);
    }
  }
  return e;
}

BsdfEval BaseBsdf::evaluate(const Outgoing& out, const glm::vec3& wi) const {
  if (!out.valid) return {};
  return eval_local(out, to_oriented_local(out, wi));
}

BsdfEval BaseBsdf::evaluate(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(outgoing(wo), wi); }

glm::vec3 BaseBsdf::eval(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(wo, wi).f; }

float BaseBsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(wo, wi).pdf; }

std::optional<BsdfSample> BaseBsdf::sample(const glm::vec3& wo, float u_split, glm::vec2 u) const {
  return sample(outgoing(wo), u_split, u);
}

std::optional<BsdfSample> BaseBsdf::sample(const Outgoing& out, float u_split, glm::vec2 u) const {
  if (!out.valid) return std::nullopt;
  const glm::vec3& lo = out.lo;
  const bool flipped = out.flipped;
  const LobeChoice& lobes = out.lobes;
  const auto to_world = [&](const glm::vec3& wi_local) {
    return glm::normalize(frame_.to_world(flipped ? mirror_z(wi_local) : wi_local));
  };
  const glm::vec3 n(0.0f, 0.0f, 1.0f);

  glm::vec3 wi(0.0f);
  // The lobe is chosen by u.x, which is then rescaled to [0, 1) within the chosen lobe's
  // interval: each lobe's directions come from a stratified part of the 2D set.
  constexpr float kBelowOne = 0.99999994f;
  if (u.x < lobes.interface || (lobes.diffuse == 0.0f && lobes.interface > 0.0f)) {
    if (lobes.interface < 1.0f) u.x = std::min(u.x / lobes.interface, kBelowOne);
    if (split_at_normal_) {
      const InterfaceSplit split = interface_split(lo, n);
      if (u_split < split.reflect) {
        if (ggx_.smooth()) {
          const float p = lobes.interface * split.reflect;
          const glm::vec3 throughput = specular_tint(lo.z, fresnel_.reflectance(lo.z, fresnel_eta_));
          return BsdfSample{to_world(glm::vec3(-lo.x, -lo.y, lo.z)), throughput / p, p, true, false};
        }
        wi = reflect_about(lo, ggx_.sample_visible(lo, u));
        if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface
      } else if (split.refract > 0.0f) {  // a delta refraction: smooth, index-matched or thin
        // Through a thin wall the direction is kept: wo mirrored, then mirrored through the plane.
        const auto refracted = thin_walled_ ? std::optional<glm::vec3>(-lo) : refract_about(lo, n, eta_);
        if (!refracted) return std::nullopt;
        const float p = lobes.interface * split.refract;
        const glm::vec3 fr = fresnel_.reflectance(lo.z, fresnel_eta_);
        const glm::vec3 throughput = (base_weight(fr) * transmission_) * base_color_;
        return BsdfSample{to_world(*refracted), throughput / p, p, true, true};
      } else {
        return std::nullopt;
      }
    } else {
      const glm::vec3 m = ggx_.sample_visible(lo, u);
      const InterfaceSplit split = interface_split(lo, m);
      if (u_split < split.reflect) {
        wi = reflect_about(lo, m);
        if (!(wi.z > 0.0f)) return std::nullopt;  // reflected below the surface
      } else if (split.refract > 0.0f && thin_walled_) {
        wi = mirror_z(reflect_about(lo, m));
        if (!(wi.z < 0.0f)) return std::nullopt;  // its mirror image reflected below the surface
      } else if (split.refract > 0.0f) {
        const auto refracted = refract_about(lo, m, eta_);
        if (!refracted || !(refracted->z < 0.0f)) return std::nullopt;  // refracted back up
        wi = *refracted;
      } else {
        return std::nullopt;
      }
    }
  } else if (lobes.diffuse > 0.0f) {
    if (lobes.interface > 0.0f) u.x = std::min((u.x - lobes.interface) / lobes.diffuse, kBelowOne);
    wi = sample_cosine_hemisphere(u);
  } else {
    return std::nullopt;  // nothing scatters
  }

  // Weight and pdf of the direction as the caller will see it: after the round trip to
  // world space, so that pdf(wo, sample.wi) returns exactly sample.pdf. (At grazing angles
  // the round trip moves a narrow lobe's half vector by a visible fraction of alpha.)
  const glm::vec3 wi_world = to_world(wi);
  const glm::vec3 li = to_oriented_local(out, wi_world);
  const BsdfEval e = eval_local(out, li);
  if (!(e.pdf > 0.0f)) return std::nullopt;
  return BsdfSample{wi_world, e.f / e.pdf, e.pdf, false, li.z < 0.0f};
}

}  // namespace lancer
