// The BSDF of a shading point, as every integrator that scatters by the glTF material builds
// and folds it (the path tracer, the photon mappers' camera and photon paths).
#pragma once

#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf.h"
#include "render/drawn_triangle.h"
#include "render/shading_inputs.h"

namespace lancer {

// The layered glTF BSDF of `si` in its shading frame (si.tangent is unit and orthogonal to
// si.ns already: evaluate_shading), seen from the side the ray came from.
inline Bsdf surface_bsdf(const ShadingInputs& si) {
  BsdfInputs inputs{si.base_color, si.metallic,       si.roughness,   si.ior,
                    si.specular,   si.specular_color, si.transmission, si.thin_walled};
  inputs.clearcoat = si.clearcoat;
  inputs.clearcoat_roughness = si.clearcoat_roughness;
  inputs.clearcoat_normal = si.clearcoat_normal;
  inputs.sheen_color = si.sheen_color;
  inputs.sheen_roughness = si.sheen_roughness;
  return Bsdf(inputs, ShadingFrame::from_orthonormal(si.ns, si.tangent), si.front_face);
}

// A ray leaving the shading point along unit `dir`, its origin pushed off the triangle just
// far enough that it cannot hit it again, for this exact direction (ray_offset.h).
inline Ray leaving_ray(const Scene& scene, const ShadingInputs& si, const glm::vec3& dir) {
  Ray r;
  r.org = leaving_offset(scene, si).origin(dir);
  r.dir = dir;
  r.time = si.time;
  return r;
}

// Beer-Lambert absorption inside a KHR_materials_volume boundary: sigma_a =
// -ln(attenuationColor) / attenuationDistance, or nothing (false). A thin wall encloses no
// volume, whatever its attenuation says.
inline bool volume_absorption(const ShadingInputs& si, glm::vec3& sigma_a) {
  if (si.thin_walled || !(si.attenuation_distance > 0.0f) || !std::isfinite(si.attenuation_distance)) return false;
  const glm::vec3 c = glm::max(si.attenuation_color, glm::vec3(1e-6f));
  sigma_a = -glm::log(c) / si.attenuation_distance;
  return true;
}

// The BSDF at a shading point seen from wo, folded where the shading and geometric normals
// disagree (shading_inputs.h): what a path, a photon and a gather ask of a surface. `si` must
// outlive it.
struct SurfaceScattering {
  const ShadingInputs& si;
  Bsdf bsdf;
  Bsdf::Outgoing out;
  bool leaning;  // ns != ng: some directions fold

  SurfaceScattering(const ShadingInputs& s, const glm::vec3& wo)
      : si(s), bsdf(surface_bsdf(s)), out(bsdf.outgoing(wo)), leaning(s.ns != s.ng) {}

  // f |cos(wi, ns)| and the density, folded.
  BsdfEval evaluate(const glm::vec3& wi) const {
    if (!leaning) return bsdf.evaluate(out, wi);
    return evaluate_folded<BsdfEval>(si, wi, [&](const glm::vec3& w) { return bsdf.evaluate(out, w); });
  }
  // A sampled direction, folded, with the density multiple importance sampling sees: the
  // drawn density plus that of the direction's other preimage near a leaning normal (the
  // mirror has Jacobian 1, so the weight f / pdf stays). nullopt: absorbed, or folded out of
  // reach.
  std::optional<BsdfSample> sample(float u_split, glm::vec2 u) const {
    std::optional<BsdfSample> bs = bsdf.sample(out, u_split, u);
    if (!bs) return bs;
    const glm::vec3 drawn = bs->wi;
    if (leaning && !fold_direction(si, bs->wi)) return std::nullopt;
    if (leaning && !bs->delta) {
      if (bs->wi != drawn)
        bs->pdf += bsdf.evaluate(out, bs->wi).pdf;
      else if (const glm::vec3 m = mirror_through_surface(si, bs->wi); !sides_agree(si, m))
        bs->pdf += bsdf.evaluate(out, m).pdf;
    }
    return bs;
  }
};

}  // namespace lancer
