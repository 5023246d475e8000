#include "render/shading_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/geometric.hpp>

#include "render/drawn_triangle.h"
#include "render/normal_mapping.h"
#include "render/surface.h"
#include "render/texture.h"

namespace lancer {

namespace {

// The barycentric blend of triangle `tri`'s three corner values.
template <typename T>
T interpolate(const std::vector<T>& corners, std::size_t tri, float w, float u, float v) {
  const T* c = &corners[3 * tri];
  return w * c[0] + u * c[1] + v * c[2];
}

float coverage(const Material& m, float alpha) {
  switch (m.alpha_mode) {
    case AlphaMode::Opaque:
      return 1.0f;
    case AlphaMode::Mask:
      return alpha >= m.alpha_cutoff ? 1.0f : 0.0f;
    case AlphaMode::Blend:
      break;
  }
  return alpha;
}

// The tangent frame (xyz unit and orthogonal to `n`, w handedness) for the triangle's
// normal map, per the rules in shading_inputs.h; w = 0 when there is none.
glm::vec4 normal_map_frame(const Scene& scene, std::size_t tri, const Instance* inst, std::uint8_t flags, float w,
                           float u, float v, const glm::vec3& n, const TextureRef& normal_texture) {
  if (flags & kHasTangents) {
    glm::vec4 t = interpolate(scene.tangents, tri, w, u, v);
    float handedness = scene.tangents[3 * tri].w < 0.0f ? -1.0f : 1.0f;
    if (inst) {
      // Each corner's tangent in world space and unit, as a flattened copy stores it; a
      // mirror turns the frame's handedness.
      const glm::vec4* c = &scene.tangents[3 * tri];
      glm::vec3 sum(0.0f);
      const float weight[3] = {w, u, v};
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 xyz = vector_to_world(inst, glm::vec3(c[k]));
        const float len = glm::length(xyz);
        sum += weight[k] * (len > 0.0f ? xyz / len : xyz);
      }
      t = glm::vec4(sum, t.w);
      if (mirrors(inst)) handedness = -handedness;
    }
    return glm::vec4(orthogonal_tangent(glm::vec3(t), n), handedness);
  }
  const bool set1 = normal_texture.texcoord == 1;
  const bool has_uv = set1 ? (flags & kHasTexcoords1) != 0 : (flags & kHasTexcoords) != 0;
  if (!has_uv) return glm::vec4(0.0f);
  const std::vector<glm::vec2>& texcoords = set1 ? scene.texcoords1 : scene.texcoords;
  const TriangleCorners corners = drawn_corners(scene, std::uint32_t(tri), inst);
  glm::vec3 p[3];
  glm::vec2 uv[3];
  for (int k = 0; k < 3; ++k) {
    p[k] = corners[std::size_t(k)];
    uv[k] = transform_uv(normal_texture, texcoords[3 * tri + std::size_t(k)]);
  }
  return triangle_tangent(p, uv, n);
}

}  // namespace

float surface_coverage(const Scene& scene, const Ray& ray, const Hit& hit) {
  const Material& m = scene.materials[scene.material_id[hit.prim]];
  if (culls_back_faces(m) && !hits_front_face(scene, hit.prim, hit.instance, ray)) return 0.0f;
  if (m.alpha_mode == AlphaMode::Opaque) return 1.0f;
  const std::size_t tri = hit.prim;
  const float w = 1.0f - hit.u - hit.v, u = hit.u, v = hit.v;
  const std::uint8_t flags = tri < scene.attrib_flags.size() ? scene.attrib_flags[tri] : 0;
  float alpha = m.base_color.a;
  if (m.base_color_texture.present()) {
    const glm::vec2 uv0 = flags & kHasTexcoords ? interpolate(scene.texcoords, tri, w, u, v) : glm::vec2(0.0f);
    const glm::vec2 uv1 =
        (flags & kHasTexcoords1) && !scene.texcoords1.empty() ? interpolate(scene.texcoords1, tri, w, u, v) : glm::vec2(0.0f);
    alpha *= sample_texture(scene, m.base_color_texture, uv0, uv1, TexelEncoding::Linear).a;
  }
  if (flags & kHasColors) alpha *= interpolate(scene.colors, tri, w, u, v).a;
  return coverage(m, alpha);
}

ShadingInputs evaluate_shading(const Scene& scene, const Ray& ray, const Hit& hit, const SurfaceGeometry* geometry) {
  // Geometry exactly as the Whitted integrator sees it.
  const DrawnInstance drawn(scene, hit.instance, ray.time);
  const SurfacePoint sp = make_surface_point(scene, ray, hit, drawn.get(), geometry);
  const std::size_t tri = hit.prim;
  const float w = 1.0f - hit.u - hit.v, u = hit.u, v = hit.v;
  const std::uint8_t flags = tri < scene.attrib_flags.size() ? scene.attrib_flags[tri] : 0;
  const Material& m = *sp.material;

  ShadingInputs si;
  si.p = sp.p;
  si.front_face = sp.front_face;
  si.material = sp.material;
  si.prim = hit.prim;
  si.instance = hit.instance;
  si.time = ray.time;
  si.drawn = drawn;
  if (flags & kHasTexcoords) si.uv0 = interpolate(scene.texcoords, tri, w, u, v);
  if ((flags & kHasTexcoords1) && !scene.texcoords1.empty()) si.uv1 = interpolate(scene.texcoords1, tri, w, u, v);

  // Most factors have no texture: answer those here, without the call.
  auto lookup = [&](const TextureRef& ref, TexelEncoding encoding) {
    return ref.present() ? sample_texture(scene, ref, si.uv0, si.uv1, encoding) : glm::vec4(1.0f);
  };
  glm::vec4 base = m.base_color * lookup(m.base_color_texture, TexelEncoding::Srgb);
  // COLOR_0 multiplies the base colour and its alpha (glTF 2.0, "Metallic-Roughness Material").
  if (flags & kHasColors) base *= interpolate(scene.colors, tri, w, u, v);
  si.base_color = glm::vec3(base);
  si.alpha = !sp.front_face && culls_back_faces(m) ? 0.0f : coverage(m, base.a);
  const glm::vec4 metal_rough = lookup(m.metallic_roughness_texture, TexelEncoding::Linear);
  si.metallic = m.metallic * metal_rough.b;
  si.roughness = m.roughness * metal_rough.g;
  si.emission = m.emission() * glm::vec3(lookup(m.emissive_texture, TexelEncoding::Srgb));
  si.ior = m.ior;
  si.specular = m.specular * lookup(m.specular_texture, TexelEncoding::Linear).a;
  si.specular_color = m.specular_color * glm::vec3(lookup(m.specular_color_texture, TexelEncoding::Srgb));
  si.transmission = m.transmission * lookup(m.transmission_texture, TexelEncoding::Linear).r;
  si.thickness = m.thickness * lookup(m.thickness_texture, TexelEncoding::Linear).g;
  si.thin_walled = is_thin_walled(m);
  si.attenuation_distance = m.attenuation_distance;
  si.attenuation_color = m.attenuation_color;

  si.unlit = m.unlit;
  if (m.clearcoat != 0.0f) {
    si.clearcoat = m.clearcoat * lookup(m.clearcoat_texture, TexelEncoding::Linear).r;
    si.clearcoat_roughness = m.clearcoat_roughness * lookup(m.clearcoat_roughness_texture, TexelEncoding::Linear).g;
  }
  if (m.sheen_color != glm::vec3(0.0f)) {
    si.sheen_color = m.sheen_color * glm::vec3(lookup(m.sheen_color_texture, TexelEncoding::Srgb));
    si.sheen_roughness = m.sheen_roughness * lookup(m.sheen_roughness_texture, TexelEncoding::Linear).a;
  }

  const float side = sp.front_face ? 1.0f : -1.0f;
  const glm::vec3 wo = -glm::normalize(ray.dir);
  si.ng = sp.ng;
  const glm::vec3 stored = sp.stored_shading_normal();
  // A normal map's normal, built on the front side, where the file's tangents and normal
  // map live, then flipped with the normals to the ray's side; w of the result's frame
  // gives the tangent.
  auto mapped = [&](const TextureRef& map, glm::vec3& tangent) {
    glm::vec4 frame = normal_map_frame(scene, tri, drawn.get(), flags, w, u, v, stored, map);
    if (frame.w == 0.0f) frame = glm::vec4(any_tangent(stored), 1.0f);
    const glm::vec3 texel(lookup(map, TexelEncoding::Linear));
    const glm::vec3 n = face_viewer(side * perturb_normal(stored, frame, texel, map.scale), sp.ng, wo);
    tangent = glm::vec3(frame);
    return n;
  };
  if (!(m.normal_texture.present() && texture_image(scene, m.normal_texture))) {
    // No normal map: the BSDFs are isotropic, so any tangent will do, and the file's
    // tangents or the UV frame need not be computed.
    si.ns = face_viewer(side * stored, sp.ng, wo);
    si.tangent = any_tangent(si.ns);
  } else {
    glm::vec3 t;
    si.ns = mapped(m.normal_texture, t);
    si.tangent = orthogonal_tangent(t, si.ns);
  }
  // The clearcoat's normal (KHR_materials_clearcoat): its own normal map, else the
  // interpolated normal, never the base's normal map.
  si.clearcoat_normal = si.ns;
  if (si.clearcoat > 0.0f) {
    if (m.clearcoat_normal_texture.present() && texture_image(scene, m.clearcoat_normal_texture)) {
      glm::vec3 t;
      si.clearcoat_normal = mapped(m.clearcoat_normal_texture, t);
    } else if (m.normal_texture.present()) {
      si.clearcoat_normal = face_viewer(side * stored, sp.ng, wo);
    }
  }
  return si;
}

glm::vec3 bent_shading_normal(const glm::vec3& ng, const glm::vec3& ns, const glm::vec3& wo) {
  const glm::vec3 image = 2.0f * glm::dot(ns, wo) * ns - wo;
  const float height = std::min(0.9f * glm::dot(wo, ng), 0.01f);
  const float image_height = glm::dot(image, ng);
  if (image_height >= height) return ns;
  const glm::vec3 along = image - image_height * ng;  // the image's azimuth in the tangent plane
  const float along_length = glm::length(along);
  if (!(along_length > 1e-6f)) return ng;
  const glm::vec3 lifted = (std::sqrt(std::max(0.0f, 1.0f - height * height)) / along_length) * along + height * ng;
  const glm::vec3 half = wo + lifted;
  const float half_length = glm::length(half);
  if (!(half_length > 1e-6f)) return ng;
  const glm::vec3 bent = half / half_length;
  return glm::dot(bent, wo) > 0.0f ? bent : ng;
}

}  // namespace lancer
