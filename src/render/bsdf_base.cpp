#include "render/bsdf_base.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace lancer {
namespace {

// Smallest selection weight of a non-delta lobe that exists. The albedo estimates are taken
// at wo only and can be 0 where the lobe is not (a black metal at normal incidence); the
// floor keeps every direction the lobe reaches sampled.
constexpr float kMinLobeEstimate = 0.02f;

// Clamp to [0, 1]; NaN becomes 0.
float unit_clamp(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

using base_lobes::average;
using base_lobes::mirror_z;

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

// ---- BaseBsdf --------------------------------------------------------------------------

namespace {

// The macroscopic refraction's n(far side) / n(wo side): a thin wall has air on both sides,
// so light leaves it unbent; an unusable ior does not refract.
float refraction_eta(const BaseFresnel& mix, bool thin_walled) {
  return mix.can_refract() && !thin_walled ? mix.fresnel_eta() : 1.0f;
}

}  // namespace

BaseBsdf::BaseBsdf(const BsdfInputs& in, const ShadingFrame& frame, bool entering)
    : frame_(frame),
      mix_(in, entering),
      ggx_(unit_clamp(in.roughness) * unit_clamp(in.roughness)),
      eta_(refraction_eta(mix_, in.thin_walled)),
      entering_(entering),
      thin_walled_(in.thin_walled),
      diffuse_(mix_),
      reflection_(mix_, ggx_),
      thin_wall_(mix_, ggx_, in.thin_walled),
      refraction_(mix_, ggx_, in.thin_walled, eta_),
      split_at_normal_(ggx_.smooth() || delta_transmission()) {}

bool BaseBsdf::has_delta() const { return (reflection_.exists() && reflection_.smooth()) || delta_transmission(); }

bool BaseBsdf::is_delta_only() const {
  return has_delta() && !diffuse_.exists() && !reflection_.rough() && !rough_transmission();
}

float BaseBsdf::delta_probability(const Outgoing& out) const {
  // sample()'s choice: the interface with probability lobes.interface (all of it when there is
  // no diffuse lobe), then reflection or transmission at the normal where a delta lobe decides.
  if (!out.valid || !split_at_normal_ || !(out.lobes.interface > 0.0f)) return 0.0f;
  const float interface = out.lobes.diffuse == 0.0f ? 1.0f : out.lobes.interface;
  const InterfaceSplit split = interface_split_at_normal(out.lo);
  float p = 0.0f;
  if (reflection_.smooth()) p += split.reflect;
  if (delta_transmission()) p += split.refract;
  return interface * p;
}

bool BaseBsdf::picks_delta(const Outgoing& out, float u_split, glm::vec2 u) const {
  // sample()'s choices, in its order.
  if (!out.valid || !split_at_normal_) return false;
  const LobeChoice& lobes = out.lobes;
  if (!(u.x < lobes.interface || (lobes.diffuse == 0.0f && lobes.interface > 0.0f))) return false;
  const InterfaceSplit split = interface_split_at_normal(out.lo);
  if (u_split < split.reflect) return reflection_.smooth();
  return split.refract > 0.0f && delta_transmission();
}

BaseBsdf::Outgoing BaseBsdf::outgoing(const glm::vec3& wo) const {
  Outgoing out;
  out.wo = wo;
  out.lo = frame_.to_local(wo);
  if (!(out.lo.z != 0.0f)) return out;  // in the tangent plane, or NaN
  out.valid = true;
  out.flipped = out.lo.z < 0.0f;
  if (out.flipped) out.lo = mirror_z(out.lo);
  out.local.lo = out.lo;
  if (!ggx_.smooth()) {
    out.local.lambda_o = ggx_.lambda(out.lo);
    out.local.g1_o = 1.0f / (1.0f + out.local.lambda_o);
  }
  // Clamped at the smallest normal float: for a subnormal lo.z, Lambda(lo) is infinite and
  // G1, G2 are 0, and 0 times a finite factor stays 0 (an infinite one would give NaN).
  out.local.inv_4cos_o = 1.0f / (4.0f * std::max(out.lo.z, std::numeric_limits<float>::min()));
  out.lobes = choose_lobes(out.lo);
  return out;
}

inline glm::vec3 BaseBsdf::to_oriented_local(const Outgoing& out, const glm::vec3& wi) const {
  const glm::vec3 li = frame_.to_local(wi);
  return out.flipped ? mirror_z(li) : li;
}

inline float BaseBsdf::transmission_weight(const glm::vec3& wo, const glm::vec3& m, const glm::vec3& fr) const {
  return thin_wall_.weight(mix_, wo, m, fr) + refraction_.weight(mix_, wo, m, fr);
}

inline BaseBsdf::InterfaceSplit BaseBsdf::interface_split(const glm::vec3& wo, const glm::vec3& m, float cos_wo_m,
                                                          const glm::vec3& fr) const {
  const float r = reflection_.weight(mix_, cos_wo_m, fr);
  const float t = transmission_weight(wo, m, fr);
  const float sum = r + t;
  if (!(sum > 0.0f)) return {};
  return {r / sum, t / sum};
}

BaseBsdf::InterfaceSplit BaseBsdf::interface_split_at_normal(const glm::vec3& wo) const {
  return interface_split(wo, glm::vec3(0.0f, 0.0f, 1.0f), wo.z, mix_.reflectance(wo.z));
}

std::optional<glm::vec3> BaseBsdf::transmitted_direction(const glm::vec3& wo, const glm::vec3& m) const {
  return thin_wall_.exists() ? thin_wall_.direction(wo, m) : refraction_.direction(wo, m);
}

std::optional<glm::vec3> BaseBsdf::delta_transmitted_direction(const glm::vec3& wo) const {
  return thin_wall_.exists() ? thin_wall_.delta_direction(wo) : refraction_.delta_direction(wo);
}

BaseBsdf::LobeChoice BaseBsdf::choose_lobes(const glm::vec3& wo) const {
  // Albedo estimates with the facet normal replaced by n: exact for the delta lobes.
  const glm::vec3 fr = mix_.reflectance(wo.z);
  const float base = mix_.base_weight(fr) * mix_.base_color_average();
  float interface = reflection_.weight(mix_, wo.z, fr) + thin_wall_.estimate(mix_, wo, base) +
                    refraction_.estimate(mix_, wo, base);
  float diffuse = 0.0f;
  if (reflection_.rough() || rough_transmission()) interface = std::max(interface, kMinLobeEstimate);
  if (diffuse_.exists()) diffuse = std::max(diffuse_.estimate(mix_, base), kMinLobeEstimate);
  const float sum = interface + diffuse;
  if (!(sum > 0.0f)) return {};
  return {interface / sum, diffuse / sum, sum};
}

template <class Transmission>
BsdfEval BaseBsdf::eval_transmitted(const Transmission& lobe, const Outgoing& out, const glm::vec3& wi) const {
  const std::optional<glm::vec3> m = lobe.facet_normal(out.lo, wi);
  if (!m) return {};
  const float cos_wo_m = glm::dot(out.lo, *m);
  const glm::vec3 fr = mix_.reflectance(cos_wo_m);
  const LobeValue v = lobe.eval(mix_, out.local, wi, *m, fr);
  BsdfEval e{v.f, 0.0f};
  if (out.lobes.interface > 0.0f)
    e.pdf = out.lobes.interface * interface_split(out.lo, *m, cos_wo_m, fr).refract * v.density;
  return e;
}

// f * |cos(wi)| and the sampling density together: the lobes above the surface share the
// half vector and its Fresnel factor. `out.lobes` is only read for the density.
BsdfEval BaseBsdf::eval_local(const Outgoing& out, const glm::vec3& wi) const {
  const glm::vec3& wo = out.lo;
  const LobeChoice& lobes = out.lobes;
  if (wi.z < 0.0f) {
    if (!rough_transmission()) return {};
    return thin_wall_.exists() ? eval_transmitted(thin_wall_, out, wi) : eval_transmitted(refraction_, out, wi);
  }
  BsdfEval e;
  if (!(wi.z > 0.0f) || (!diffuse_.exists() && !reflection_.rough())) return e;
  const HalfVectorSum h = reflection_half_sum(wo, wi);
  const float cos_wo_h = h.cos_with(wo);
  const glm::vec3 fr = mix_.reflectance(cos_wo_h);
  if (reflection_.rough()) {
    const glm::vec3 tint = mix_.specular_tint(cos_wo_h, fr);
    const LobeValue r = reflection_.eval(out.local, wi, h, tint);
    e.f += r.f;
    if (lobes.interface > 0.0f) {
      // The probability of reflecting rather than transmitting at h (at n where a delta
      // transmission decides it there); without transmission r / (r + 0) = 1 for any r > 0.
      const float reflect = split_at_normal_       ? interface_split_at_normal(wo).reflect
                            : !has_transmission() ? (average(tint) > 0.0f ? 1.0f : 0.0f)
                                                  : interface_split(wo, h.unit(), cos_wo_h, fr).reflect;
      e.pdf += lobes.interface * reflect * r.density;
    }
  }
  if (diffuse_.exists()) {
    const LobeValue d = diffuse_.eval(mix_, wi, fr);
    e.f += d.f;
    e.pdf += lobes.diffuse * d.density;
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
  const LobeChoice& lobes = out.lobes;
  const auto to_world = [&](const glm::vec3& wi_local) {
    return glm::normalize(frame_.to_world(out.flipped ? mirror_z(wi_local) : wi_local));
  };

  std::optional<glm::vec3> wi;
  // The lobe is chosen by u.x, which is then rescaled to [0, 1) within the chosen lobe's
  // interval: each lobe's directions come from a stratified part of the 2D set.
  constexpr float kBelowOne = 0.99999994f;
  if (u.x < lobes.interface || (lobes.diffuse == 0.0f && lobes.interface > 0.0f)) {
    if (lobes.interface < 1.0f) u.x = std::min(u.x / lobes.interface, kBelowOne);
    if (split_at_normal_) {
      const InterfaceSplit split = interface_split_at_normal(lo);
      if (u_split < split.reflect) {
        if (reflection_.smooth()) {
          const float p = lobes.interface * split.reflect;
          const glm::vec3 throughput = reflection_.mirror_throughput(mix_, lo);
          return BsdfSample{to_world(glm::vec3(-lo.x, -lo.y, lo.z)), throughput / p, p, true, false};
        }
        wi = ReflectionLobe::direction(lo, ggx_.sample_visible(lo, u));
      } else if (split.refract > 0.0f) {  // a delta transmission: smooth, index-matched or thin
        const std::optional<glm::vec3> through = delta_transmitted_direction(lo);
        if (!through) return std::nullopt;
        const float p = lobes.interface * split.refract;
        const glm::vec3 throughput =
            (mix_.base_weight(mix_.reflectance(lo.z)) * mix_.transmission()) * mix_.base_color();
        return BsdfSample{to_world(*through), throughput / p, p, true, true};
      }
    } else {
      const glm::vec3 m = ggx_.sample_visible(lo, u);
      const float cos_wo_m = glm::dot(lo, m);
      const InterfaceSplit split = interface_split(lo, m, cos_wo_m, mix_.reflectance(cos_wo_m));
      if (u_split < split.reflect)
        wi = ReflectionLobe::direction(lo, m);
      else if (split.refract > 0.0f)
        wi = transmitted_direction(lo, m);
    }
  } else if (lobes.diffuse > 0.0f) {
    if (lobes.interface > 0.0f) u.x = std::min((u.x - lobes.interface) / lobes.diffuse, kBelowOne);
    wi = DiffuseLobe::sample(u);
  }
  if (!wi) return std::nullopt;  // absorbed, or the drawn direction left its lobe's domain

  // Weight and pdf of the direction as the caller will see it: after the round trip to
  // world space, so that pdf(wo, sample.wi) returns exactly sample.pdf. (At grazing angles
  // the round trip moves a narrow lobe's half vector by a visible fraction of alpha.)
  const glm::vec3 wi_world = to_world(*wi);
  const glm::vec3 li = to_oriented_local(out, wi_world);
  const BsdfEval e = eval_local(out, li);
  if (!(e.pdf > 0.0f)) return std::nullopt;
  return BsdfSample{wi_world, e.f / e.pdf, e.pdf, false, li.z < 0.0f};
}

}  // namespace lancer
