// The geometry of many hits at once: the point, the two normals and the side that
// make_surface_point (surface.h) computes, bit for bit, for several hits per vector
// (surface_batch-inl.h, one solver per ISA). The path tracer asks it for every live path's
// hit before shading them: one hit at a time, the point's double-precision sum and the two
// normalisations were 6 % of a Cornell box render. A first piece of shading several paths
// per vector.
//
// The split, as ray_offset_batch.h's: generic code (surface_batch.cpp) lays each hit out as
// a lane (its triangle's corners and stored normals, the barycentrics, the ray's direction);
// the ISA solver does make_surface_point's float and double operations in its order (the
// build passes -ffp-contract=off); a hit it leaves (drawn through an instance, a triangle
// whose normal is too small for float) is left to make_surface_point.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/ray.h"
#include "scene/scene.h"
#include "simd/isa.h"

namespace lancer {

// What make_surface_point derives from the corners, the stored normals and the ray.
struct SurfaceGeometry {
  glm::vec3 p{0.0f}, ng{0.0f}, ns{0.0f};
  bool front_face = true;
  bool valid = false;  // false: left to make_surface_point (no hit, an instance, a degenerate normal)
};

// geometry[i] for hits[i] of rays[i], i < count, with the solver of `isa` (scalar: every hit
// is left to make_surface_point). Returns how many valid hits were left.
int surface_geometry(const Scene& scene, const Ray* rays, const Hit* hits, int count, SurfaceGeometry* geometry,
                     Isa isa);
// The same with the best ISA this CPU runs, chosen once.
int surface_geometry(const Scene& scene, const Ray* rays, const Hit* hits, int count, SurfaceGeometry* geometry);

namespace surface_batch {

inline constexpr int kMaxLanes = 64;  // lanes per solver call (a multiple of every vector width)

struct Lanes {
  alignas(64) float corner[9][kMaxLanes];  // vertex i, axis k at [3 i + k]
  alignas(64) float normal[9][kMaxLanes];  // the stored corner normals (where has_normals)
  alignas(64) float u[kMaxLanes];
  alignas(64) float v[kMaxLanes];
  alignas(64) float dir[3][kMaxLanes];
  alignas(64) std::int32_t has_normals[kMaxLanes];
};

struct Out {
  alignas(64) float p[3][kMaxLanes];
  alignas(64) float ng[3][kMaxLanes];
  alignas(64) float ns[3][kMaxLanes];
  alignas(64) std::int32_t front[kMaxLanes];
};

// Solves lanes [0, count): bit i set where lane i was computed. Lanes up to the next
// multiple of 8 are set (copies of lane 0) and may be read.
using SolveLanesFn = std::uint64_t (*)(const Lanes& lanes, int count, Out& out);

}  // namespace surface_batch
}  // namespace lancer
