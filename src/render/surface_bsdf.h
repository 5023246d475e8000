// The BSDF of a shading point, as every integrator that scatters by the glTF material builds
// it, with the wedge between the shading and geometric tangent planes handled as
// shading_inputs.h says (the path tracer, the light tracer, the photon mappers' camera and
// photon paths).
#pragma once

#include <cmath>
#include <optional>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray_offset.h"
#include "render/bsdf.h"
#include "render/drawn_triangle.h"
#include "render/shading_inputs.h"

namespace lancer {

// The layered glTF BSDF of `si` in `frame`, its coat around `clearcoat_normal` (si's own
// unless the normals are bent: SurfaceScattering), seen from the side the ray came from.
inline Bsdf surface_bsdf(const ShadingInputs& si, const ShadingFrame& frame, const glm::vec3& clearcoat_normal) {
  BsdfInputs inputs{si.base_color, si.metallic,       si.roughness,   si.ior,
                    si.specular,   si.specular_color, si.transmission, si.thin_walled};
  inputs.clearcoat = si.clearcoat;
  inputs.clearcoat_roughness = si.clearcoat_roughness;
  inputs.clearcoat_normal = clearcoat_normal;
  inputs.sheen_color = si.sheen_color;
  inputs.sheen_roughness = si.sheen_roughness;
  return Bsdf(inputs, frame, si.front_face);
}
// si.tangent is unit and orthogonal to si.ns already (evaluate_shading).
inline Bsdf surface_bsdf(const ShadingInputs& si) {
  return surface_bsdf(si, ShadingFrame::from_orthonormal(si.ns, si.tangent), si.clearcoat_normal);
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

// The BSDF at a shading point seen from wo, with the wedge between the shading and the
// geometric tangent planes handled as shading_inputs.h describes (the normal bent and the
// wedge dropped, or every direction folded): what a path, a photon and a gather ask of a
// surface. `si` must outlive it.
struct SurfaceScattering {
  const ShadingInputs& si;
  Bsdf bsdf;
  Bsdf::Outgoing out;
  bool leaning;  // ns != ng: the wedge exists
  bool bends;    // bends_normal: the normal bends with the viewer, else directions fold
  glm::vec3 n;   // the BSDF's normal: si.ns, or bent for wo

  SurfaceScattering(const ShadingInputs& s, const glm::vec3& wo)
      : si(s), bsdf(surface_bsdf(s)), leaning(s.ns != s.ng), bends(false), n(s.ns) {
    if (bends_normal(s, bsdf.has_delta())) {
      bends = true;
      n = bent_shading_normal(s.ng, s.ns, wo);
      // A rough coat's own normal bends too (as Cycles bends each closure's normal).
      const bool coat_normal = s.clearcoat > 0.0f && glm::dot(s.clearcoat_normal, s.clearcoat_normal) > 0.0f;
      const glm::vec3 coat = coat_normal ? bent_shading_normal(s.ng, s.clearcoat_normal, wo) : s.clearcoat_normal;
      if (n != s.ns || coat != s.clearcoat_normal)
        bsdf = surface_bsdf(s, ShadingFrame::from_normal_tangent(n, s.tangent), coat);
    }
    out = bsdf.outgoing(wo);
  }

  // f |cos(wi, n)| and the density.
  BsdfEval evaluate(const glm::vec3& wi) const { return evaluate(out, wi); }
  // The same for the BSDF seen from `view` instead of wo (a photon's adjoint: the camera
  // would look from where it goes on).
  BsdfEval evaluate_seen_from(const glm::vec3& view, const glm::vec3& wi) const {
    if (bends) return SurfaceScattering(si, view).evaluate(wi);
    return evaluate(bsdf.outgoing(view), wi);
  }
  // A sampled direction, dropped (nullopt, as when absorbed) or folded where it falls in the
  // wedge. A folded one's density, as multiple importance sampling sees it, is the drawn
  // density plus that of the direction's other preimage (the mirror has Jacobian 1, so the
  // weight f / pdf stays); dropping moves no direction.
  std::optional<BsdfSample> sample(float u_split, glm::vec2 u) const {
    std::optional<BsdfSample> bs = bsdf.sample(out, u_split, u);
    if (!bs || !leaning) return bs;
    if (bends) return sides_agree(si.ng, n, bs->wi) ? bs : std::nullopt;
    const glm::vec3 drawn = bs->wi;
    if (!fold_direction(si, bs->wi)) return std::nullopt;
    if (!bs->delta) {
      if (bs->wi != drawn)
        bs->pdf += bsdf.evaluate(out, bs->wi).pdf;
      else if (const glm::vec3 m = mirror_through_surface(si, bs->wi); !sides_agree(si, m))
        bs->pdf += bsdf.evaluate(out, m).pdf;
    }
    return bs;
  }

 private:
  BsdfEval evaluate(const Bsdf::Outgoing& from, const glm::vec3& wi) const {
    if (!leaning) return bsdf.evaluate(from, wi);
    return evaluate_across_wedge<BsdfEval>(si, bends, n, wi, [&](const glm::vec3& w) { return bsdf.evaluate(from, w); });
  }
};

}  // namespace lancer
