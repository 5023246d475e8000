// The BSDF of a shading point, as every integrator that scatters by the glTF material builds
// it (the path tracer, the photon mapper's camera and photon paths).
#pragma once

#include "render/bsdf.h"
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

}  // namespace lancer
