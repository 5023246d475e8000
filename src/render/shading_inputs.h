// Everything a BSDF needs at a ray hit: geometry, the normal-mapped shading frame and
// the glTF material evaluated with its textures.
//
// Material (glTF 2.0 spec, "Materials", and the KHR_materials_* extensions): every
// factor is multiplied by its texture at the hit's UV,
//   base_color, alpha = baseColorFactor * baseColorTexture (sRGB RGB, linear A)
//   metallic = metallicFactor * B, roughness = roughnessFactor * G of metallicRoughnessTexture
//   emission = emissiveFactor * emissiveStrength * emissiveTexture (sRGB)
//   transmission = transmissionFactor * R of transmissionTexture
//   specular = specularFactor * A of specularTexture
//   specular_color = specularColorFactor * specularColorTexture (sRGB)
//   thickness = thicknessFactor * G of thicknessTexture
//   thin_walled = (thicknessFactor == 0), the texture aside (see is_thin_walled)
// and an absent texture counts as 1. alpha is the coverage after alphaMode: 1 for
// OPAQUE, 0 or 1 for MASK (opaque when alpha >= alphaCutoff), the value itself for
// BLEND. The occlusion texture is ignored: ambient occlusion approximates shadowing
// from indirect light, which a path tracer computes itself, so applying it would darken
// twice. Vertex colours (COLOR_0) are not read.
//
// Geometry: ng comes from the triangle's winding (cross(b - a, c - a) is the front) and
// ns from the interpolated normals, or equals ng when the primitive has none; both are
// flipped to the side the ray came from, exactly as make_surface_point() does (p, ng,
// front_face and, without a normal map, the interpolated ns agree with it). Then:
//  - Normal map: in the frame of the file's tangents (interpolated, w from the first
//    corner) when the triangle has them, else of triangle_tangent() over the normal
//    texture's UV set after its KHR_texture_transform (normal_mapping.h). A triangle
//    without usable UVs gets an arbitrary frame around ns.
//  - ns is then kept on the viewer's side by face_viewer() (normal_mapping.h).
//  - tangent is unit and orthogonal to the final ns: along the frame's T where a normal
//    map is applied, any tangent (Duff et al. 2017) otherwise; the BSDF frame is
//    (tangent, cross(ns, tangent), ns). Handedness is not carried: isotropic BSDFs do not
//    need it, nor the file's tangents without a normal map.
//  - uv0 / uv1 are the interpolated TEXCOORD_0 / _1, (0, 0) when the triangle has none
//    (what a GPU reads for a missing attribute).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "scene/scene.h"

namespace lancer {

struct ShadingInputs {
  glm::vec3 p{0.0f};
  glm::vec3 ng{0.0f};       // unit geometric normal on the ray's side
  glm::vec3 ns{0.0f};       // unit shading normal after the normal map, on the ray's side
  glm::vec3 tangent{0.0f};  // unit, orthogonal to ns
  glm::vec2 uv0{0.0f};
  glm::vec2 uv1{0.0f};
  glm::vec3 base_color{1.0f};  // linear
  float alpha = 1.0f;          // coverage after alphaMode
  float metallic = 1.0f;
  float roughness = 1.0f;  // perceptual (GGX alpha = roughness^2)
  glm::vec3 emission{0.0f};  // emitted radiance, W / (sr m^2); which sides emit is the integrator's choice
  float ior = 1.5f;
  float specular = 1.0f;
  glm::vec3 specular_color{1.0f};  // linear
  float transmission = 0.0f;
  float thickness = 0.0f;
  bool thin_walled = true;  // is_thin_walled(*material)
  float attenuation_distance = 0.0f;  // infinity: no attenuation
  glm::vec3 attenuation_color{1.0f};
  bool front_face = true;  // the ray hit the side cross(b - a, c - a) points to
  const Material* material = nullptr;
  std::uint32_t prim = kNoHit;  // the triangle hit
};

// Whether `m` is a thin wall (KHR_materials_volume, "Properties": thicknessFactor 0, the
// default, is thin-walled, anything else makes the mesh a volume boundary). The thickness
// texture plays no part: "Ray-tracers should ignore the thickness texture ... it is still
// necessary to check the thicknessFactor to determine whether the object is thin-walled or
// volumetric" ("Thickness Texture"), so a closed mesh is a volume at every point or at none.
inline bool is_thin_walled(const Material& m) { return !(m.thickness > 0.0f); }

// `hit` must be valid and come from `ray` against `scene.triangles`.
ShadingInputs evaluate_shading(const Scene& scene, const Ray& ray, const Hit& hit);

}  // namespace lancer
