// SPD "rings": objects made of six pentagonal rings, stacked as a pyramid that the
// viewer looks at from its apex, with a white wall behind for the shadows. Three
// lights; most objects are partly hidden, and there is no background in view.
//
// One object: six regular pentagons of circumradius 1 / (1 + r) around a common centre,
// in the six planes perpendicular to an icosahedron's five-fold axes (one pentagon in
// the xy plane; the other five tipped by 2 acos(cos 60 / sin 36), about 63.4 degrees,
// about x, then turned about z by 36 + 72k degrees). Each ring is five spheres of
// radius r = 0.07412 at the corners and five cylinders of the same radius along the
// sides, so an object has 30 spheres and 30 cylinders. Layer d (0-based, n layers)
// is a (d + 1) x (d + 1) square of objects two units apart, at depth
// (d + 1) / sin(22.5 degrees).
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "scene/spd_common.h"

namespace lancer::spd {

namespace {

constexpr int kMaxLayers = 50;
constexpr double kTubeRadius = 0.07412;

std::uint64_t object_count(int layers) {
  const auto n = std::uint64_t(layers);
  return n * (n + 1) * (2 * n + 1) / 6;
}

std::uint64_t rings_triangles(int size, const SpdOptions& options) {
  return 30 * object_count(size) * (sphere_triangles(options) + cylinder_triangles(options)) + 2;
}

// The 30 ring corners of one object around the origin: ring c is corners 5c .. 5c + 4.
std::array<glm::dvec3, 30> ring_corners() {
  constexpr double kPi = std::numbers::pi;
  const double scale = 1.0 / (1.0 + kTubeRadius);
  std::array<glm::dvec3, 30> corner{};
  for (int j = 0; j < 5; ++j)
    corner[std::size_t(j)] = scale * glm::dvec3(std::cos(j * 2.0 * kPi / 5.0), std::sin(j * 2.0 * kPi / 5.0), 0.0);
  const glm::dmat3 tip = rotation({1.0, 0.0, 0.0}, 2.0 * std::acos(std::cos(kPi / 3.0) / std::sin(kPi / 5.0)));
  for (int ring = 1; ring < 6; ++ring) {
    const glm::dmat3 turn = rotation({0.0, 0.0, 1.0}, kPi * (2.0 * (ring - 1) + 1.0) / 5.0);
    for (int j = 0; j < 5; ++j) corner[std::size_t(5 * ring + j)] = turn * (tip * corner[std::size_t(j)]);
  }
  return corner;
}

void build_rings(SpdEmitter& out, int size) {
  const double depth_step = 1.0 / std::sin(std::numbers::pi / 8.0);
  const glm::dvec3 eye(-1.0, -depth_step, 0.5);
  const glm::dvec3 at = eye + glm::dvec3(0.0, 1.0, 0.0);
  out.set_view({eye, at, {0.0, 0.0, 1.0}, 45.0});
  out.add_lights({{3.0, -depth_step, 3.0}, {-4.0, -depth_step, 1.0}, {2.0, -depth_step, -4.0}}, at);

  // The wall behind the last layer just fills the 45-degree view (plus 1%), facing -y.
  const std::uint32_t white = out.add_material(diffuse_material("wall", {1.0f, 1.0f, 1.0f}));
  const double wall_y = depth_step * (size + 1);
  const double w = 1.01 * (wall_y - eye.y) * std::tan(std::numbers::pi / 8.0);
  out.quad({eye.x + w, wall_y, eye.z + w}, {eye.x - w, wall_y, eye.z + w}, {eye.x - w, wall_y, eye.z - w},
           {eye.x + w, wall_y, eye.z - w}, white);

  // Ring c of every object has colour c (red, green, blue and their complements; the
  // SPD's Kd 0.5, Ks 0.2 is diffuse here). Emitting colour by colour keeps each
  // material's triangles together.
  const std::array<glm::vec3, 6> colours = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1),
                                            glm::vec3(0, 1, 1), glm::vec3(1, 0, 1), glm::vec3(1, 1, 0)};
  const std::array<glm::dvec3, 30> corner = ring_corners();
  for (int c = 0; c < 6; ++c) {
    const std::uint32_t material =
        out.add_material(diffuse_material("ring " + std::to_string(c), colours[std::size_t(c)]));
    for (int layer = 0; layer < size; ++layer)
      for (int iz = 0; iz <= layer; ++iz)
        for (int ix = 0; ix <= layer; ++ix) {
          const glm::dvec3 offset(2.0 * ix - layer, depth_step * (layer + 1), 2.0 * iz - layer);
          for (int j = 0; j < 5; ++j) {
            const glm::dvec3 a = corner[std::size_t(5 * c + j)] + offset;
            const glm::dvec3 b = corner[std::size_t(5 * c + (j + 1) % 5)] + offset;
            out.sphere(a, kTubeRadius, material);
            out.cylinder(a, b, kTubeRadius, material);
          }
        }
  }
}

}  // namespace

const Generator kRings{"rings", {1, kMaxLayers}, rings_triangles, build_rings};

}  // namespace lancer::spd
