// Eric Haines' Standard Procedural Databases (SPD; "A Proposal for Standard Graphics
// Environments", IEEE CG&A 7(11), 1987) as triangle meshes at any size factor. Our own
// generators, written from the published descriptions of each database: the same
// shapes, layout, viewpoint, lights and surface colours, with curved surfaces
// tessellated here (spheres: icospheres; cylinders: capped prisms).
//
// Coordinates: the SPD is modelled with +z up in a left-handed frame. Every point is
// mapped (x, y, z) -> (x, z, y), a mirror that gives glTF's right-handed, +y-up frame
// and shows the same image as the original renderers. Triangles wind counter-
// clockwise seen from outside (the geometric normal points out).
//
// Closed meshes: each sphere, cylinder, tetrahedron and gear is a closed, consistently
// oriented mesh (every edge shared by exactly two of its triangles, once in each
// direction; shared corners have bit-identical positions). Single squares (floors,
// walls) and the mount terrain are open surfaces facing the viewer/up, as in the SPD.
// Closed pieces may touch or overlap one another (rings' cylinders end inside their
// joint spheres), again as in the SPD.
//
// Triangle counts, with the tessellation of SpdOptions:
//   S = 20 * 4^s triangles per sphere (s = sphere_subdivisions)
//   C = 4 * k triangles per cylinder (k = cylinder_sides: 2k on the side, k per cap)
//
//   balls (sphereflake; size = recursion depth, 0..6):
//     spheres (9^(n+1) - 1) / 8, each S triangles, plus a floor square (2):
//     T = S * (9^(n+1) - 1) / 8 + 2
//   tetra (Sierpinski tetrahedron; size = depth, 1..12):
//     4^(n-1) tetrahedra of 4 triangles: T = 4^n
//   mount (fractal terrain; size = subdivision depth, 0..12):
//     a 2^n x 2^n grid of 2 triangles per cell plus 4 glass spheres:
//     T = 2 * 4^n + 4 * S
//   rings (size = pyramid layers; the base layer has n x n objects, 1..50):
//     O = n (n + 1) (2n + 1) / 6 objects of 6 pentagonal rings, each ring 5 spheres
//     and 5 cylinders, plus a backdrop square: T = 30 * O * (S + C) + 2
//   gears (size = gears per side of an n x n x n grid, 1..44):
//     each gear a 36-tooth prism: 2 faces of 144 triangles (fans around the axis)
//     and 144 side quads: T = 576 * n^3 + 2 (the ground square)
//
// Every generator refuses, before allocating, a scene of more than kSpdMaxTriangles
// (a Scene costs about 150 bytes per triangle, so the cap is about 7.5 GB).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace lancer {

struct SpdOptions {
  int sphere_subdivisions = 2;  // 0..8: S = 20 * 4^s triangles per sphere
  int cylinder_sides = 16;      // 3..1024: C = 4 * k triangles per cylinder
};

inline constexpr int kSpdMinSphereSubdivisions = 0;
inline constexpr int kSpdMaxSphereSubdivisions = 8;
inline constexpr int kSpdMinCylinderSides = 3;
inline constexpr int kSpdMaxCylinderSides = 1024;
inline constexpr std::uint64_t kSpdMaxTriangles = 50'000'000;

struct SpdSizeRange {
  int min = 0;
  int max = 0;
};

// The generator names, in alphabetical order: balls, gears, mount, rings, tetra.
const std::vector<std::string_view>& spd_names();

// The valid sizes of one generator. Throws std::invalid_argument for an unknown name.
SpdSizeRange spd_size_range(std::string_view name);

// The triangle count make_spd would produce, from the formulas above, without building
// anything. Throws std::invalid_argument for an unknown name, a size out of range or
// options out of range; the count itself may exceed kSpdMaxTriangles.
std::uint64_t spd_triangle_count(std::string_view name, int size, const SpdOptions& options = {});

// Builds the database: triangles, materials, the SPD viewpoint as camera 0 (aspect 1,
// as the SPD renders 512 x 512) and the SPD lights as point lights. Throws
// std::invalid_argument as spd_triangle_count does, and also when the count exceeds
// kSpdMaxTriangles; the message names the generator and the valid range. The same
// arguments give bit-identical scenes.
Scene make_spd(std::string_view name, int size, const SpdOptions& options = {});

}  // namespace lancer
