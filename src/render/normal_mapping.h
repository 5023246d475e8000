// Tangent frames and tangent-space normal maps (glTF 2.0 spec, "Meshes" and
// "material.normalTextureInfo").
//
// Frame convention: tangent T along increasing u, bitangent B = cross(N, T) * w, where w
// (+1 or -1) is the handedness, and a normal-map texel (r, g, b) means the direction
// (2r - 1) T + (2g - 1) B + (2b - 1) N. glTF's normal maps have +X right and +Y up in
// the image, and glTF's v grows downwards (UV (0, 0) is the top-left), so B points along
// decreasing v: B ~ -dP/dv.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace lancer {

// The per-triangle tangent of a triangle with corners p[3] and texture coordinates
// uv[3], for the unit shading normal `n`: dP/du from the UV gradient (solve
// [p1 - p0, p2 - p0] = [dP/du, dP/dv] [uv1 - uv0, uv2 - uv0]), made orthogonal to n and
// unit; w = +1 when cross(n, T) points along -dP/dv, else -1 (mirrored UVs).
// Returns w = 0 when the UVs are degenerate (zero UV area) or T is parallel to n.
//
// This is not full MikkTSpace (which glTF recommends when a file has no TANGENT): MikkTSpace
// averages the face tangents of the triangles sharing a vertex (weighted by corner
// angle, split at UV seams and mirror lines) and interpolates those vertex tangents, so
// its frame turns smoothly across a curved mesh. Here T is constant over each triangle
// (only the Gram-Schmidt step against the interpolated normal varies), so normal maps
// baked with MikkTSpace on curved, UV-mapped surfaces can show faint facets; on planar
// or flat-shaded surfaces the two agree. Handedness uses glTF's downward v, like
// MikkTSpace run on glTF UVs with its sign negated (what three.js does for glTF).
glm::vec4 triangle_tangent(const glm::vec3 p[3], const glm::vec2 uv[3], const glm::vec3& n);

// Any unit vector orthogonal to unit `n`, continuous except across n.z = 0's sign change
// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
glm::vec3 any_tangent(const glm::vec3& n);

// `tangent` with its component along unit `n` removed, normalised; any_tangent(n) when
// that leaves (almost) nothing.
glm::vec3 orthogonal_tangent(const glm::vec3& tangent, const glm::vec3& n);

// The normal-mapped shading normal: texel `rgb` (linear, [0, 1]) decoded to
// (2 rgb - 1) * (scale, scale, 1) (the spec's normalTextureInfo.scale scales X and Y
// only) in the frame (T, cross(n, T) * tangent.w, n), then normalised. `n` is the unit
// shading normal, tangent.xyz a unit vector orthogonal to it. A texel that decodes to
// the zero vector leaves `n` unchanged.
glm::vec3 perturb_normal(const glm::vec3& n, const glm::vec4& tangent, const glm::vec3& rgb, float scale);

// The smallest cosine between the viewer and a shading normal that face_viewer allows.
inline constexpr float kMinShadingCosine = 1e-3f;

// Keeps a shading normal on the viewer's side. `ng` is the unit geometric normal on the
// side the ray came from, `wo` the unit direction back to the ray origin (dot(ng, wo) >=
// 0). A shading normal (interpolated or normal-mapped) may lean so far that the viewer
// is behind it (dot(ns, wo) < kMinShadingCosine), which would make a BSDF evaluated in
// its frame see the viewer below the surface. Such a normal is bent back within the
// plane of ns and wo: its part orthogonal to wo, p = ns - dot(ns, wo) wo, keeps its
// direction and the result is sqrt(1 - c^2) p/|p| + c wo with c = kMinShadingCosine.
// When p leans to the far side of the surface (dot(p, ng) <= 0) the part of ng
// orthogonal to wo is used instead, so the result also stays in ng's hemisphere. A
// normal already facing the viewer is returned unchanged.
glm::vec3 face_viewer(const glm::vec3& ns, const glm::vec3& ng, const glm::vec3& wo);

}  // namespace lancer
