// Procedural geometry for tests and benchmarks: closed spheres and boxes, quads, and
// seeded random triangle soups. Everything goes through SceneBuilder, so the usual
// checks apply, and each call ends with SceneBuilder::finish(): a scene that had no
// materials gets the default material (id 0), and a material id that does not exist
// in scene.materials is refused with a SceneError.
//
// Closed meshes compute every vertex once into an indexed table and build triangles
// from indices, so adjacent triangles share bit-identical corners (the watertight
// kernel's no-crack guarantee depends on that). All triangles wind counter-clockwise
// seen from outside, so geometric normals cross(p1 - p0, p2 - p0) point outward.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/triangle_soa.h"
#include "scene/scene.h"

namespace lancer {

// UV sphere: `stacks` bands from pole to pole (>= 2) and `slices` around (>= 3).
// Poles are single vertices joined by triangle fans; the seam reuses the first
// column. Vertices: slices * (stacks - 1) + 2; triangles: 2 * slices * (stacks - 1).
// With smooth_normals, each corner carries the unit direction from the centre;
// otherwise no normals are stored and shading uses the geometric normal.
void append_uv_sphere(Scene& scene, glm::vec3 center, float radius, int slices, int stacks,
                      std::uint32_t material, bool smooth_normals = true);

// Icosphere: the regular icosahedron with each triangle split in four `subdivisions`
// times (0..8), new vertices pushed onto the sphere. Vertices: 10 * 4^s + 2;
// triangles: 20 * 4^s. Smooth normals (unit direction from the centre).
void append_icosphere(Scene& scene, glm::vec3 center, float radius, int subdivisions,
                      std::uint32_t material);

// Two triangles (p0, p1, p2) and (p0, p2, p3); the face is counter-clockwise, seen
// from the side it faces, when the corners are given in counter-clockwise order.
void append_quad(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3,
                 std::uint32_t material);

// Closed axis-aligned box: 8 shared corners, 12 triangles facing outward. The box
// must have a positive extent on every axis.
void append_box(Scene& scene, const Bounds3& box, std::uint32_t material);

// `count` non-degenerate triangles, every corner inside `box` and every edge at most
// `max_edge` long, from a splitmix64 stream seeded with `seed`: the same arguments
// give bit-identical scenes on every platform and standard library. Material 0
// (the default material) on all triangles.
Scene make_random_triangle_soup(std::size_t count, std::uint64_t seed, Bounds3 box, float max_edge);

}  // namespace lancer
