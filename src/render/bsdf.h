// The BSDF the path tracer shades with: the glTF metallic-roughness base (bsdf_base.h) under
// the KHR_materials_sheen and KHR_materials_clearcoat layers (bsdf_lobes.h), stacked as the
// two extensions write it:
//   sheened  = sheen_brdf + base * (1 - max(sheenColor) E(|n.V|))      (KHR_materials_sheen)
//   material = sheened * (1 - clearcoat Fc(|n_c.V|)) + clearcoat Fc clearcoat_brdf
//                                                                       (KHR_materials_clearcoat)
// Both layer weights depend on wo alone, so they are computed once per shading point
// (Outgoing). The sheen shares the base's shading normal; the coat has its own (BsdfInputs::
// clearcoat_normal: the clearcoat normal map, else the interpolated normal).
//
// Adding a lobe: one type in bsdf_lobes.h (eval / sample / albedo estimate in its local
// frame), one member here, its layering weight in outgoing(), its term in evaluate() and its
// interval in sample(); no flags in the base.
//
// Sampling: one lobe (coat, sheen or base) is chosen by u.x with probabilities proportional
// to the albedo estimates times the layer weights (kMinLobeEstimate-floored for non-delta
// lobes, as in the base), and u.x is rescaled within the chosen interval (see bsdf_base.h).
// A non-delta sample's weight and pdf are those of the whole non-delta mixture, so it
// combines with light sampling by MIS; a delta sample's are exact.
//
// Simplifications (documented, not in the extensions): the layer lobes only reflect into the
// hemisphere of wo on both the shading normal's and their own normal's side (a coat whose
// normal leans away from the shading normal loses the directions between the two planes);
// the integrator then handles the whole layered BSDF's wedge (shading_inputs.h) with the
// base's shading normal. A material without sheen and clearcoat is exactly the base: every call is
// forwarded to it.
#pragma once

#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/bsdf_base.h"
#include "render/bsdf_lobes.h"

namespace lancer {

class Bsdf {
 public:
  struct Outgoing {
    BaseBsdf::Outgoing base;
    glm::vec3 co{0.0f};         // wo in the coat's frame, mirrored so that co.z > 0
    bool coat_flipped = false;  // wo was below the coat's tangent plane
    float coat_weight = 0.0f;   // clearcoat Fc(|n_c.wo|): the coat's share
    float under_coat = 1.0f;    // 1 - coat_weight: what reaches the sheen and the base
    float base_scale = 1.0f;    // under_coat times the sheen's albedo scaling
    float p_coat = 0.0f, p_sheen = 0.0f, p_base = 1.0f;  // lobe choice
  };

  Bsdf(const BsdfInputs& in, const ShadingFrame& frame, bool entering);

  glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const;
  float pdf(const glm::vec3& wo, const glm::vec3& wi) const;
  BsdfEval evaluate(const glm::vec3& wo, const glm::vec3& wi) const;
  std::optional<BsdfSample> sample(const glm::vec3& wo, float u_split, glm::vec2 u) const;

  Outgoing outgoing(const glm::vec3& wo) const;
  BsdfEval evaluate(const Outgoing& out, const glm::vec3& wi) const;
  std::optional<BsdfSample> sample(const Outgoing& out, float u_split, glm::vec2 u) const;

  bool reads_split() const { return base_.reads_split(); }
  bool has_delta() const { return base_.has_delta() || (coat_.exists() && coat_.smooth()); }
  bool is_delta_only() const {
    if (!layered_) return base_.is_delta_only();
    return has_delta() && !base_.has_non_delta() && !sheen_.exists() && coat_.smooth();
  }
  // A Lambertian or sheen lobe: where photon mapping's visible points stay (glossy lobes
  // alone pass the camera path on).
  bool has_diffuse() const { return base_.has_diffuse() || sheen_.exists(); }
  // The probability that sample(out, ...) returns a delta sample (when its direction exists).
  float delta_probability(const Outgoing& out) const;
  // Whether sample(out, u_split, u) picks a delta lobe, whether or not its direction exists.
  bool picks_delta(const Outgoing& out, float u_split, glm::vec2 u) const;
  bool entering() const { return base_.entering(); }
  float eta() const { return base_.eta(); }
  bool thin_walled() const { return base_.thin_walled(); }
  bool layered() const { return layered_; }

 private:
  glm::vec3 oriented_local(const ShadingFrame& frame, bool flipped, const glm::vec3& wi) const;

  BaseBsdf base_;
  ClearcoatLobe coat_;
  ShadingFrame coat_frame_;
  SheenLobe sheen_;
  bool layered_;  // a coat or a sheen exists
};

}  // namespace lancer
