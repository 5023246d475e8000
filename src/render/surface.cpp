#include "render/surface.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "render/drawn_triangle.h"
#include "render/surface_batch.h"

namespace lancer {

glm::vec3 base_color_at(const Scene& /*scene*/, const Material& m, std::uint32_t /*prim*/, float /*u*/,
                        float /*v*/) {
  // Untextured on purpose: see surface.h; evaluate_shading() samples the texture.
  return glm::vec3(m.base_color);
}

bool hits_front_face(const Scene& scene, std::uint32_t prim, std::uint32_t instance, const Ray& ray) {
  const DrawnInstance drawn(scene, instance, ray.time);
  const Instance* inst = drawn.get();
  const glm::vec3& dir = ray.dir;
  const glm::vec3 ng = drawn_front_normal(drawn_corners(scene, prim, inst), inst);
  const float len = glm::length(ng);
  // make_surface_point's fallback normal, -dir, is met on its front side.
  return !(len > 0.0f && std::isfinite(len)) || glm::dot(ng / len, dir) <= 0.0f;
}

SurfacePoint make_surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
  const DrawnInstance drawn(scene, hit.instance, ray.time);
  return make_surface_point(scene, ray, hit, drawn.get());
}

namespace {

// The point, the normals facing the ray and the side: what surface_batch-inl.h computes for
// several hits per vector, with these very operations in this order.
void surface_geometry_here(const Scene& scene, const Ray& ray, const Hit& hit, const Instance* inst,
                           SurfacePoint& sp) {
  const std::uint32_t i = hit.prim;
  const TriangleCorners corners = drawn_corners(scene, i, inst);
  const glm::vec3 a = corners[0], b = corners[1], c = corners[2];
  const float w = 1.0f - hit.u - hit.v;
  // In double: any barycentric combination lies on the triangle's plane, so only the
  // arithmetic can push p off it. In float that error scales with the vertices (a 2 km
  // floor puts p 1e-4 off the plane, beyond what offset_ray_origin allows for a point
  // near the origin); in double it is just the final rounding, relative to p itself.
  const double du = hit.u, dv = hit.v, dw = 1.0 - du - dv;
  sp.p = glm::vec3(dw * glm::dvec3(a) + du * glm::dvec3(b) + dv * glm::dvec3(c));

  // The scene builder drops zero-area triangles, so the cross product is non-zero; a
  // triangle too small for float still gets a usable normal from the direction alone.
  glm::vec3 ng = drawn_front_normal(corners, inst);
  const float len = glm::length(ng);
  ng = len > 0.0f && std::isfinite(len) ? ng / len : -glm::normalize(ray.dir);

  glm::vec3 ns = ng;
  if (i < scene.attrib_flags.size() && (scene.attrib_flags[i] & kHasNormals)) {
    const glm::vec3* stored = &scene.normals[3 * static_cast<std::size_t>(i)];
    glm::vec3 n[3] = {stored[0], stored[1], stored[2]};
    // Each corner's normal in world space and unit, as a flattened copy stores it.
    if (inst)
      for (glm::vec3& nk : n) nk = glm::normalize(normal_to_world(inst, nk));
    const glm::vec3 interp = w * n[0] + hit.u * n[1] + hit.v * n[2];
    const float ilen = glm::length(interp);
    if (ilen > 1e-12f && std::isfinite(ilen)) ns = interp / ilen;
  }

  sp.front_face = glm::dot(ng, ray.dir) <= 0.0f;
  if (!sp.front_face) {
    ng = -ng;
    ns = -ns;
  }
  sp.ng = ng;
  sp.ns = ns;
}

}  // namespace

SurfacePoint make_surface_point(const Scene& scene, const Ray& ray, const Hit& hit, const Instance* inst,
                                const SurfaceGeometry* geometry) {
  const std::uint32_t i = hit.prim;
  SurfacePoint sp;
  sp.prim = i;
  sp.instance = hit.instance;
  if (geometry && geometry->valid) {
    sp.p = geometry->p;
    sp.ng = geometry->ng;
    sp.ns = geometry->ns;
    sp.front_face = geometry->front_face;
  } else {
    surface_geometry_here(scene, ray, hit, inst, sp);
  }
  sp.material = &scene.materials[scene.material_id[i]];
  sp.base_color = base_color_at(scene, *sp.material, i, hit.u, hit.v);
  return sp;
}

}  // namespace lancer
