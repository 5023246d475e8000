#include "render/bsdf.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace lancer {
namespace {

// As bsdf_base.cpp: the smallest selection weight of a non-delta lobe that exists.
constexpr float kMinLobeEstimate = 0.02f;
constexpr float kBelowOne = 0.99999994f;

glm::vec3 mirror_z(const glm::vec3& v) { return {v.x, v.y, -v.z}; }

ShadingFrame coat_frame(const BsdfInputs& in, const ShadingFrame& frame) {
  const glm::vec3 n = in.clearcoat_normal;
  const float len2 = glm::dot(n, n);
  if (!(len2 > 0.0f) || !std::isfinite(len2)) return frame;
  return ShadingFrame::from_normal(n / std::sqrt(len2));
}

}  // namespace

Bsdf::Bsdf(const BsdfInputs& in, const ShadingFrame& frame, bool entering)
    : base_(in, frame, entering),
      coat_(in.clearcoat, in.clearcoat_roughness),
      coat_frame_(coat_.exists() ? coat_frame(in, frame) : frame),  // read only where a coat exists
      sheen_(in.sheen_color, in.sheen_roughness),
      layered_(coat_.exists() || sheen_.exists()) {}

inline glm::vec3 Bsdf::oriented_local(const ShadingFrame& frame, bool flipped, const glm::vec3& wi) const {
  const glm::vec3 l = frame.to_local(wi);
  return flipped ? mirror_z(l) : l;
}

Bsdf::Outgoing Bsdf::outgoing(const glm::vec3& wo) const {
  Outgoing out{.base = base_.outgoing(wo)};  // built in place, not assigned over a default
  if (!layered_ || !out.base.valid) return out;
  float e_coat = 0.0f, e_sheen = 0.0f;
  if (coat_.exists()) {
    out.co = coat_frame_.to_local(wo);
    out.coat_flipped = out.co.z < 0.0f;
    if (out.coat_flipped) out.co = mirror_z(out.co);
    if (out.co.z > 0.0f) {
      out.coat_weight = coat_.layer_weight(out.co);
      e_coat = coat_.smooth() ? out.coat_weight : std::max(coat_.albedo(out.co), kMinLobeEstimate);
    }
  }
  out.under_coat = 1.0f - out.coat_weight;
  out.base_scale = out.under_coat;
  if (sheen_.exists()) {
    out.base_scale *= sheen_.base_scale(out.base.lo);
    e_sheen = out.under_coat * std::max(sheen_.albedo(out.base.lo), kMinLobeEstimate);
  }
  const float e_base = out.base_scale * BaseBsdf::albedo_estimate(out.base);
  const float sum = e_coat + e_sheen + e_base;
  if (!(sum > 0.0f)) {
    out.p_base = 0.0f;
    return out;
  }
  out.p_coat = e_coat / sum;
  out.p_sheen = e_sheen / sum;
  out.p_base = e_base / sum;
  return out;
}

float Bsdf::delta_probability(const Outgoing& out) const {
  if (!layered_) return base_.delta_probability(out.base);
  if (!out.base.valid) return 0.0f;
  return (coat_.smooth() ? out.p_coat : 0.0f) + out.p_base * base_.delta_probability(out.base);
}

bool Bsdf::picks_delta(const Outgoing& out, float u_split, glm::vec2 u) const {
  if (!layered_) return base_.picks_delta(out.base, u_split, u);
  if (!out.base.valid) return false;
  if (u.x < out.p_coat) return coat_.smooth();
  if (u.x < out.p_coat + out.p_sheen || !(out.p_base > 0.0f)) return false;
  u.x = std::min((u.x - out.p_coat - out.p_sheen) / out.p_base, kBelowOne);
  return base_.picks_delta(out.base, u_split, u);
}

BsdfEval Bsdf::evaluate(const Outgoing& out, const glm::vec3& wi) const {
  if (!layered_) return base_.evaluate(out.base, wi);
  if (!out.base.valid) return {};
  BsdfEval e;
  if (out.base_scale > 0.0f) {
    const BsdfEval b = base_.evaluate(out.base, wi);
    e.f = out.base_scale * b.f;
    e.pdf = out.p_base * b.pdf;
  }
  const glm::vec3 li = oriented_local(base_.frame(), out.base.flipped, wi);
  if (!(li.z > 0.0f)) return e;  // the layers only reflect
  if (sheen_.exists()) {
    const BsdfEval s = sheen_.eval(out.base.lo, li);
    e.f += out.under_coat * s.f;
    e.pdf += out.p_sheen * s.pdf;
  }
  if (out.coat_weight > 0.0f && !coat_.smooth()) {
    const BsdfEval c = coat_.eval(out.co, oriented_local(coat_frame_, out.coat_flipped, wi));
    e.f += c.f;
    e.pdf += out.p_coat * c.pdf;
  }
  return e;
}

BsdfEval Bsdf::evaluate(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(outgoing(wo), wi); }

glm::vec3 Bsdf::eval(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(wo, wi).f; }

float Bsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const { return evaluate(wo, wi).pdf; }

std::optional<BsdfSample> Bsdf::sample(const glm::vec3& wo, float u_split, glm::vec2 u) const {
  return sample(outgoing(wo), u_split, u);
}

std::optional<BsdfSample> Bsdf::sample(const Outgoing& out, float u_split, glm::vec2 u) const {
  if (!layered_) return base_.sample(out.base, u_split, u);
  if (!out.base.valid) return std::nullopt;
  // The lobe by u.x, which is then rescaled to [0, 1) within the chosen lobe's interval.
  glm::vec3 wi_world(0.0f);
  if (u.x < out.p_coat) {
    u.x = std::min(u.x / out.p_coat, kBelowOne);
    const std::optional<glm::vec3> ci = coat_.sample(out.co, u);
    if (!ci) return std::nullopt;
    wi_world = glm::normalize(coat_frame_.to_world(out.coat_flipped ? mirror_z(*ci) : *ci));
    if (!(oriented_local(base_.frame(), out.base.flipped, wi_world).z > 0.0f)) return std::nullopt;
    if (coat_.smooth())
      return BsdfSample{wi_world, glm::vec3(out.coat_weight / out.p_coat), out.p_coat, true, false, true};
  } else if (u.x < out.p_coat + out.p_sheen) {
    u.x = std::min((u.x - out.p_coat) / out.p_sheen, kBelowOne);
    const std::optional<glm::vec3> li = sheen_.sample(out.base.lo, u);
    if (!li) return std::nullopt;
    wi_world = glm::normalize(base_.frame().to_world(out.base.flipped ? mirror_z(*li) : *li));
  } else if (out.p_base > 0.0f) {
    u.x = std::min((u.x - out.p_coat - out.p_sheen) / out.p_base, kBelowOne);
    std::optional<BsdfSample> bs = base_.sample(out.base, u_split, u);
    if (!bs) return std::nullopt;
    if (bs->delta) {
      bs->weight *= out.base_scale / out.p_base;
      bs->pdf *= out.p_base;
      return bs;
    }
    wi_world = bs->wi;
  } else {
    return std::nullopt;  // nothing scatters
  }
  // Weight and density of the whole non-delta mixture at the direction the caller sees.
  const BsdfEval e = evaluate(out, wi_world);
  if (!(e.pdf > 0.0f)) return std::nullopt;
  const bool transmitted = oriented_local(base_.frame(), out.base.flipped, wi_world).z < 0.0f;
  return BsdfSample{wi_world, e.f / e.pdf, e.pdf, false, transmitted};
}

}  // namespace lancer
