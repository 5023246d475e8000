// SPD "balls", the sphereflake: a sphere of radius 0.5 at the origin carries nine
// spheres of a third of its radius on its surface, each of which carries nine more,
// to the given depth, above a square floor. Three lights.
//
// In a frame whose +z is the direction a sphere grew in, its nine children sit at
// distance r + r/3 from its centre: six around the equator at azimuths 15 + 60k
// degrees, and three at elevation asin(sqrt(2/3)) (about 54.7 degrees) at azimuths
// 45 + 120k. The frame of a child is the rotation taking +z to its own direction by
// the shortest arc, so no child ever grows back into its parent.
#include <array>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "scene/spd_common.h"

namespace lancer::spd {

namespace {

constexpr int kMaxDepth = 6;

std::uint64_t sphere_count(int depth) {
  std::uint64_t power = 9;  // 9^(depth + 1)
  for (int i = 0; i < depth; ++i) power *= 9;
  return (power - 1) / 8;
}

std::uint64_t balls_triangles(int size, const SpdOptions& options) {
  return sphere_count(size) * sphere_triangles(options) + 2;
}

// The nine child directions in the frame whose +z is the growth direction.
std::array<glm::dvec3, 9> child_directions() {
  constexpr double kDegree = std::numbers::pi / 180.0;
  std::array<glm::dvec3, 9> d{};
  for (int k = 0; k < 6; ++k) {
    const double azimuth = (15.0 + 60.0 * k) * kDegree;
    d[std::size_t(k)] = {std::cos(azimuth), std::sin(azimuth), 0.0};
  }
  const double horizontal = std::sqrt(1.0 / 3.0), vertical = std::sqrt(2.0 / 3.0);
  for (int k = 0; k < 3; ++k) {
    const double azimuth = (45.0 + 120.0 * k) * kDegree;
    d[std::size_t(6 + k)] = {horizontal * std::cos(azimuth), horizontal * std::sin(azimuth), vertical};
  }
  return d;
}

// The rotation taking +z to the unit vector `dir` by the shortest arc.
glm::dmat3 rotation_from_z(const glm::dvec3& dir) {
  if (dir.z >= 1.0 - 1e-12) return glm::dmat3(1.0);
  if (dir.z <= -1.0 + 1e-12) return rotation({0.0, 1.0, 0.0}, std::numbers::pi);
  return rotation(glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), dir)), std::acos(dir.z));
}

struct Flake {
  SpdEmitter& out;
  std::uint32_t material;
  std::array<glm::dvec3, 9> children = child_directions();

  // Depth-first: the sphere, then each child's whole subtree.
  void grow(const glm::dvec3& centre, double radius, const glm::dvec3& direction, int depth) {
    out.sphere(centre, radius, material);
    if (depth == 0) return;
    const glm::dmat3 frame = rotation_from_z(direction);
    const double child_radius = radius / 3.0;
    for (const glm::dvec3& local : children) {
      const glm::dvec3 dir = frame * local;
      grow(centre + (radius + child_radius) * dir, child_radius, dir, depth - 1);
    }
  }
};

void build_balls(SpdEmitter& out, int size) {
  out.set_view({{2.1, 1.3, 1.7}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0});
  out.add_lights({{4.0, 3.0, 2.0}, {1.0, -4.0, 4.0}, {-3.0, 1.0, 5.0}}, {0.0, 0.0, 0.0});

  // The floor: a 24 x 24 square touching the bottom of the big sphere, facing up.
  const std::uint32_t floor = out.add_material(diffuse_material("floor", {1.0f, 0.75f, 0.33f}));
  const double half = 12.0, z = -0.5;
  out.quad({half, half, z}, {-half, half, z}, {-half, -half, z}, {half, -half, z}, floor);

  // The spheres are shiny in the SPD (Kd 0.5, Ks 0.5): mirrors here.
  Flake flake{out, out.add_material(mirror_material("sphereflake", {1.0f, 0.9f, 0.7f}))};
  flake.grow({0.0, 0.0, 0.0}, 0.5, {0.0, 0.0, 1.0}, size);
}

}  // namespace

const Generator kBalls{"balls", {0, kMaxDepth}, balls_triangles, build_balls};

}  // namespace lancer::spd
