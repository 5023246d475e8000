// World-space triangles in structure-of-arrays form: the input of every accelerator.
// Readers fill it; accelerators never see a file format or a material.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

#include "simd/aligned_vector.h"

namespace lancer {

struct Bounds3 {
  glm::vec3 lo{kBoundsEmpty()};
  glm::vec3 hi{-kBoundsEmpty()};

  static constexpr float kBoundsEmpty() { return 3.402823466e38f; }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const glm::vec3& p) {
    lo = glm::vec3(p.x < lo.x ? p.x : lo.x, p.y < lo.y ? p.y : lo.y, p.z < lo.z ? p.z : lo.z);
    hi = glm::vec3(p.x > hi.x ? p.x : hi.x, p.y > hi.y ? p.y : hi.y, p.z > hi.z ? p.z : hi.z);
  }
  void extend(const Bounds3& b) {
    if (b.empty()) return;
    extend(b.lo);
    extend(b.hi);
  }
  glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : hi - lo; }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
};

// Vertex k (0, 1, 2) of triangle i is (x[k][i], y[k][i], z[k][i]).
struct TriangleSoA {
  AlignedVector<float> x[3], y[3], z[3];

  std::size_t size() const { return x[0].size(); }
  bool empty() const { return size() == 0; }

  void reserve(std::size_t n) {
    for (int k = 0; k < 3; ++k) {
      x[k].reserve(n);
      y[k].reserve(n);
      z[k].reserve(n);
    }
  }

  void push_back(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3* v[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      x[k].push_back(v[k]->x);
      y[k].push_back(v[k]->y);
      z[k].push_back(v[k]->z);
    }
  }

  glm::vec3 vertex(std::size_t i, int k) const { return {x[k][i], y[k][i], z[k][i]}; }

  Bounds3 triangle_bounds(std::size_t i) const {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) b.extend(vertex(i, k));
    return b;
  }

  Bounds3 bounds() const {
    Bounds3 b;
    for (std::size_t i = 0; i < size(); ++i) b.extend(triangle_bounds(i));
    return b;
  }
};

}  // namespace lancer
