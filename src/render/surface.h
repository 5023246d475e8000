// From a ray hit to the shading point: position, normals, material and base colour.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "scene/scene.h"

namespace lancer {

struct SurfaceGeometry;  // render/surface_batch.h

struct SurfacePoint {
  glm::vec3 p{0.0f};   // from the barycentrics of the hit
  glm::vec3 ng{0.0f};  // unit geometric normal, flipped to face the incoming ray
  glm::vec3 ns{0.0f};  // unit shading normal, flipped together with ng
  // True when the ray hit the front side: the side cross(b - a, c - a) points to (CCW).
  // Shading is two-sided; only emission depends on the side.
  bool front_face = true;
  std::uint32_t prim = kNoHit;
  std::uint32_t instance = kNoHit;  // Hit::instance: drawn through scene.instancing's
  const Material* material = nullptr;
  glm::vec3 base_color{1.0f};  // linear

  // The normals as stored in the scene (front side), for the debug views.
  glm::vec3 stored_shading_normal() const { return front_face ? ns : -ns; }
};

// make_surface_point(...).front_face alone: whether `ray` meets triangle `prim`, drawn
// through `instance` (kNoHit: in world space) at the ray's time, on its front side.
bool hits_front_face(const Scene& scene, std::uint32_t prim, std::uint32_t instance, const Ray& ray);

// `hit` must be valid and come from `ray` against the scene's triangles (and instances).
SurfacePoint make_surface_point(const Scene& scene, const Ray& ray, const Hit& hit);
// The same with the hit's instance as drawn at the ray's time already at hand
// (DrawnInstance::get(), render/drawn_triangle.h; null in world space), and optionally its
// geometry already computed by surface_geometry (render/surface_batch.h; when valid).
SurfacePoint make_surface_point(const Scene& scene, const Ray& ray, const Hit& hit, const Instance* drawn,
                                const SurfaceGeometry* geometry = nullptr);

// Base colour of material `m` at barycentrics (u, v) of triangle `prim`, linear RGB:
// the material's factor only. Every integrator shades with evaluate_shading() in
// shading_inputs.h (every factor times its texture, normal maps); a SurfacePoint serves
// the geometric debug views and the ray sets.
glm::vec3 base_color_at(const Scene& scene, const Material& m, std::uint32_t prim, float u, float v);

}  // namespace lancer
