// Mesh checks for generated scenes: edge topology with vertices identified by their
// exact bits (no tolerance), and the signed volume of a closed piece.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/scene.h"

namespace lancer::test {

inline std::uint64_t bits_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

struct BitsHash {
  std::size_t operator()(const glm::vec3& p) const {
    std::uint64_t h = bits_of(p.x) * 0x9E3779B97F4A7C15ull;
    h ^= (bits_of(p.y) + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
    h ^= (bits_of(p.z) + (h << 6) + (h >> 2)) * 0x94D049BB133111EBull;
    return std::size_t(h);
  }
};
struct BitsEqual {
  bool operator()(const glm::vec3& a, const glm::vec3& b) const {
    return bits_of(a.x) == bits_of(b.x) && bits_of(a.y) == bits_of(b.y) && bits_of(a.z) == bits_of(b.z);
  }
};

// The edges of triangles [first, first + count): for each directed edge (a, b), how
// often it occurs. Vertex numbers follow first appearance.
struct EdgeUse {
  std::unordered_map<glm::vec3, std::uint32_t, BitsHash, BitsEqual> vertex;
  std::unordered_map<std::uint64_t, int> directed;  // a << 32 | b
  std::vector<glm::vec3> position;

  EdgeUse(const Scene& s, std::size_t first, std::size_t count) {
    for (std::size_t t = first; t < first + count; ++t) {
      std::uint32_t v[3];
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = s.triangles.vertex(t, k);
        const auto [it, added] = vertex.emplace(p, std::uint32_t(vertex.size()));
        if (added) position.push_back(p);
        v[k] = it->second;
      }
      for (int k = 0; k < 3; ++k) ++directed[std::uint64_t(v[k]) << 32 | v[(k + 1) % 3]];
    }
  }
  int uses(std::uint32_t a, std::uint32_t b) const {
    const auto it = directed.find(std::uint64_t(a) << 32 | b);
    return it == directed.end() ? 0 : it->second;
  }
};

// Empty when triangles [first, first + count) form a closed, consistently oriented
// mesh: every directed edge once and its reverse once. Otherwise the first problem.
inline std::string closed_mesh_problem(const Scene& s, std::size_t first, std::size_t count) {
  const EdgeUse e(s, first, count);
  for (const auto& [key, n] : e.directed) {
    const auto a = std::uint32_t(key >> 32), b = std::uint32_t(key);
    if (n != 1 || e.uses(b, a) != 1)
      return "edge " + std::to_string(a) + "->" + std::to_string(b) + " used " + std::to_string(n) +
             " times, its reverse " + std::to_string(e.uses(b, a)) + " times (triangles " + std::to_string(first) +
             ".." + std::to_string(first + count - 1) + ")";
  }
  return {};
}

// Six times the signed volume enclosed by triangles [first, first + count), in double:
// positive when a closed mesh winds counter-clockwise seen from outside.
inline double signed_volume6(const Scene& s, std::size_t first, std::size_t count) {
  double v = 0.0;
  for (std::size_t t = first; t < first + count; ++t) {
    const glm::dvec3 a(s.triangles.vertex(t, 0)), b(s.triangles.vertex(t, 1)), c(s.triangles.vertex(t, 2));
    v += glm::dot(a, glm::cross(b, c));
  }
  return v;
}

inline glm::dvec3 geometric_normal(const Scene& s, std::size_t t) {
  const glm::dvec3 a(s.triangles.vertex(t, 0)), b(s.triangles.vertex(t, 1)), c(s.triangles.vertex(t, 2));
  return glm::cross(b - a, c - a);
}

}  // namespace lancer::test
