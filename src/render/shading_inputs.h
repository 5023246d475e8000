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
//   clearcoat = clearcoatFactor * R, clearcoat_roughness = clearcoatRoughnessFactor * G
//   sheen_color = sheenColorFactor * sheenColorTexture (sRGB), sheen_roughness = factor * A
// and an absent texture counts as 1. alpha is the coverage after alphaMode: 1 for
// OPAQUE, 0 or 1 for MASK (opaque when alpha >= alphaCutoff), the value itself for
// BLEND. The occlusion texture is ignored: ambient occlusion approximates shadowing
// from indirect light, which a path tracer computes itself, so applying it would darken
// twice. Vertex colours (COLOR_0) multiply baseColor and its alpha. How the integrators use
// alpha: render/coverage.h.
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

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "render/drawn_triangle.h"
#include "scene/scene.h"

namespace lancer {

struct SurfaceGeometry;  // render/surface_batch.h

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
  // KHR_materials_clearcoat: factor * R, roughness factor * G of their textures, and the
  // coat's normal (its own normal map, else the interpolated normal; on the viewer's side).
  float clearcoat = 0.0f;
  float clearcoat_roughness = 0.0f;
  glm::vec3 clearcoat_normal{0.0f};
  // KHR_materials_sheen: colour factor * texture RGB (sRGB), roughness factor * texture A.
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
  bool unlit = false;  // KHR_materials_unlit: shows base_color, scatters nothing
  bool front_face = true;  // the ray hit the side cross(b - a, c - a) points to
  const Material* material = nullptr;
  std::uint32_t prim = kNoHit;  // the triangle hit
  std::uint32_t instance = kNoHit;  // and the instance it was drawn through (Hit::instance)
  float time = 0.0f;                // the ray's shutter time (Ray::time), for the rays that leave
  // The instance as drawn at that time (computed once per hit: a moving one interpolates).
  DrawnInstance drawn;
};

// Whether `m` is a thin wall (KHR_materials_volume, "Properties": thicknessFactor 0, the
// default, is thin-walled, anything else makes the mesh a volume boundary). The thickness
// texture plays no part: "Ray-tracers should ignore the thickness texture ... it is still
// necessary to check the thicknessFactor to determine whether the object is thin-walled or
// volumetric" ("Thickness Texture"), so a closed mesh is a volume at every point or at none.
inline bool is_thin_walled(const Material& m) { return !(m.thickness > 0.0f); }

// Whether the back side of `m`'s triangles is culled: invisible to every ray, which goes on
// past it as past a cut-out (render/coverage.h). glTF 2.0 ("Double Sided"): doubleSided
// false enables back-face culling. A volume boundary (KHR_materials_volume) keeps its back
// side, which is where a ray leaves the volume: culling it would let refracted light out of
// a glass object unrefracted and unattenuated, which is not what a rasteriser shows either.
inline bool culls_back_faces(const Material& m) { return !m.double_sided && is_thin_walled(m); }

// Whether `m` emits from the side a ray hit: a double-sided material from both sides
// ("double-sided lighting is enabled"), a single-sided one from its front only.
inline bool emits_toward(const Material& m, bool front_face) { return front_face || m.double_sided; }

// `hit` must be valid and come from `ray` against `scene.triangles`. `geometry`: the hit's
// surface_geometry (render/surface_batch.h), or null.
ShadingInputs evaluate_shading(const Scene& scene, const Ray& ray, const Hit& hit,
                               const SurfaceGeometry* geometry = nullptr);

// Where rays leave the shading point: leaving_offset (drawn_triangle.h) for its triangle,
// with the instance as evaluate_shading already moved it to the ray's time.
inline SurfaceOffset leaving_offset(const Scene& scene, const ShadingInputs& si) {
  return SurfaceOffset(si.p, si.ng, triangle_corners(scene.triangles, si.prim), si.drawn.get(), si.time);
}
// The same, built in place at the end of `offsets`: a SurfaceOffset is about 300 bytes, and
// copying a returned one into the path tracer's batch was 1-2 % of a Cornell box render.
inline SurfaceOffset& add_leaving_offset(std::vector<SurfaceOffset>& offsets, const Scene& scene,
                                         const ShadingInputs& si) {
  return offsets.emplace_back(si.p, si.ng, triangle_corners(scene.triangles, si.prim), si.drawn.get(), si.time);
}

// evaluate_shading(...).alpha alone, for the rays that only ask whether a surface is there
// (render/coverage.h): 0 on a culled back face (culls_back_faces), else 1 for an OPAQUE
// material without looking further.
float surface_coverage(const Scene& scene, const Ray& ray, const Hit& hit);

// Scattered directions and the two normals, for every integrator. A BSDF works in its
// shading frame: a direction on wo's side of its normal n is reflected, one on the other
// side transmitted. Leaving the point it must also lie on the matching side of the true
// surface (ng), else light would pass through it. The two disagree in the wedge between the
// shading and the geometric tangent planes, and what happens there is a modelling choice
// glTF leaves open. Lancer's, in two cases:
//  - A BSDF with no delta lobe and no transmission (rough opaque surfaces, most of a
//    normal-mapped glTF file) does what Cycles (the reference renderer Lancer is compared
//    with) does: it is evaluated around a bent normal (bent_shading_normal, after Cycles'
//    ensure_valid_reflection: where the viewer's mirror image about ns falls below a small
//    height over the surface, the normal becomes the half vector of the view and that image
//    lifted to the height, so a glossy lobe keeps its highlight above the surface; Cycles
//    keeps the normal's azimuth instead of the image's, which renders the still life the same
//    within 0.5 % per 32 x 32 block), and it loses what it still sends into the
//    wedge: f is 0 there, and a sample drawn into it ends the path. Folding these too, as
//    below, kept their energy but added light Cycles does not have: the normal-mapped still
//    life (scenes/textured/still-life.gltf, 256 x 256 x 1,024 spp against Cycles at 4,096)
//    came out 3.2 % brighter than Cycles, MSE 4.30e-4; dropping without bending 1.99e-4,
//    bending and dropping 1.72e-4.
//  - Every other BSDF folds (issue 20): a direction in the wedge is mirrored through the
//    geometric tangent plane. While dot(ns, ng) > 0 the image lies where both normals
//    agree, on the same side of ns, so a reflection stays a reflection and a refraction goes
//    through, and the folded BSDF scatters exactly the energy of the unfolded one:
//      f_folded(wi) = f(wi) + f(mirror(wi)) [mirror(wi) in the wedge]  for wi where they agree,
//      f_folded(wi) = 0                                                  for wi in the wedge.
//    A sample drawn from f's density and folded keeps its weight f / pdf (the mirror has
//    Jacobian 1); its density as seen by MIS is the folded sum of f's densities. Glass keeps
//    its light this way: a lossless glass sphere of 16 x 8 facets with interpolated normals
//    in a uniform field of radiance 1 (tests/render/shading_normal_render_test.cpp), mean of
//    its outer ring, 64 spp: smooth, dropping the wedge 0.955, bending 0.970 (bent normals
//    trap paths by total internal reflection along the rim), folding 1.000; rough (0.3),
//    dropping 4 % below a 64 x 32 sphere's, folding the same. And a delta lobe must not bend:
//    the bent normal depends on the viewer, so a mirror would no longer send light back the
//    way it came, and the light tracer's paths through it would not be the path tracer's.
//    (So the look of a leaning metal changes at the roughness where its lobe becomes delta,
//    alpha = 1e-3: below, the folded mirror keeps all its light; above, the bent lobe loses
//    what falls into the wedge.)
inline bool sides_agree(const glm::vec3& ng, const glm::vec3& n, const glm::vec3& wi) {
  return (wi.x * ng.x + wi.y * ng.y + wi.z * ng.z > 0.0f) == (wi.x * n.x + wi.y * n.y + wi.z * n.z > 0.0f);
}
inline bool sides_agree(const ShadingInputs& si, const glm::vec3& wi) { return sides_agree(si.ng, si.ns, wi); }

// Whether the BSDF of `si` bends its normal (the first case above) rather than folds: ns
// leans, and the material neither transmits nor has a delta lobe (`has_delta`: the
// integrator's own test of its BSDF; Bsdf::has_delta for the layered glTF BSDF).
inline bool bends_normal(const ShadingInputs& si, bool has_delta) {
  return si.ns != si.ng && !has_delta && !(si.transmission > 0.0f);
}

// wi mirrored through the geometric tangent plane.
inline glm::vec3 mirror_through_surface(const ShadingInputs& si, const glm::vec3& wi) {
  return wi - (2.0f * (wi.x * si.ng.x + wi.y * si.ng.y + wi.z * si.ng.z)) * si.ng;
}

// A scattered direction made to leave on the side both normals agree on: itself, or its
// mirror image when it lies in the wedge. False when neither does (only where wi lies in a
// tangent plane, or where dot(ns, ng) <= 0 puts the image in the wedge too).
inline bool fold_direction(const ShadingInputs& si, glm::vec3& wi) {
  if (sides_agree(si, wi)) return true;
  wi = mirror_through_surface(si, wi);
  return sides_agree(si, wi);
}

// The folded value of any quantity a BSDF gives a direction (f, its density, a cosine):
// eval(wi), plus eval of wi's mirror image when that lies in the wedge; T{} for wi in the wedge.
template <typename T, typename Eval>
T evaluate_folded(const ShadingInputs& si, const glm::vec3& wi, Eval eval) {
  if (!sides_agree(si, wi)) return T{};
  T value = eval(wi);
  const glm::vec3 m = mirror_through_surface(si, wi);
  if (!sides_agree(si, m)) value += eval(m);
  return value;
}

// The same quantity under the rule above: for a BSDF that bends (around n, bends_normal),
// eval(wi) where ng and n agree on wi's side and T{} in the wedge; for one that folds,
// evaluate_folded.
template <typename T, typename Eval>
T evaluate_across_wedge(const ShadingInputs& si, bool bends, const glm::vec3& n, const glm::vec3& wi, Eval eval) {
  if (bends) return sides_agree(si.ng, n, wi) ? eval(wi) : T{};
  return evaluate_folded<T>(si, wi, eval);
}

// The normal a BSDF that bends (bends_normal) uses seen from unit wo (on ng's side):
// ns itself when wo's mirror image about it rises at least h = min(0.9 wo.ng, 0.01) above the
// geometric tangent plane; else the half vector of wo and that image lifted to height h
// (same azimuth about ng), whose mirror image of wo is exactly the lifted one. ng where the
// image has no azimuth (it points straight into the surface), or where rounding would leave
// the result not facing wo (views within about 1e-4 of the tangent plane, with ns barely
// facing them; evaluate_shading keeps dot(ns, wo) >= 1e-3 for the camera side's wo).
glm::vec3 bent_shading_normal(const glm::vec3& ng, const glm::vec3& ns, const glm::vec3& wo);

}  // namespace lancer
