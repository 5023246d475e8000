// Rays and hit records shared by every intersector (oracle, kd-tree, packets).
#pragma once

#include <cstdint>
#include <limits>

#include <glm/vec3.hpp>

namespace lancer {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr std::uint32_t kNoHit = 0xFFFFFFFFu;

// A hit counts when tnear <= t < tfar. dir need not be normalised; t is in units of |dir|.
struct Ray {
  glm::vec3 org{0.0f};
  float tnear = 0.0f;
  glm::vec3 dir{0.0f, 0.0f, 1.0f};
  float tfar = kInfinity;
  // Where in the shutter the ray is traced, from open (0) to close (1): moving instances
  // (InstancedGeometry::motions) are met where they are then. 0 for a still scene.
  float time = 0.0f;
};

// Closest hit. (u, v) are the barycentric weights of the triangle's second and third
// vertices: p = (1 - u - v) * a + u * b + v * c.
struct Hit {
  float t = kInfinity;
  std::uint32_t prim = kNoHit;
  float u = 0.0f;
  float v = 0.0f;
  // The instance (InstancedGeometry::instances) the triangle was hit through; kNoHit in a
  // one-level scene, whose triangles are drawn once, in world space.
  std::uint32_t instance = kNoHit;

  bool valid() const { return prim != kNoHit; }
};

}  // namespace lancer
