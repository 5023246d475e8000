// Norms and limits the two-level accelerator's build checks transforms against (static
// instances in two_level.cpp, moving ones in two_level_motion.cpp).
#pragma once

#include <cmath>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "accel/instances.h"

namespace lancer::two_level {

// Transforms beyond this scale either way are refused: the error bound of two_level_ray.h
// assumes ray_to_object neither overflows nor underflows for the rays it traverses.
inline constexpr double kMaxNorm = 0x1p40;

// Infinity norm (largest row sum of magnitudes) of a column-major glm matrix.
inline double norm_inf(const glm::dmat3& m) {
  double n = 0.0;
  for (int row = 0; row < 3; ++row)
    n = std::fmax(n, std::fabs(m[0][row]) + std::fabs(m[1][row]) + std::fabs(m[2][row]));
  return n;
}
inline double norm_inf(const glm::mat3& m) { return norm_inf(glm::dmat3(m)); }

inline double norm_inf(const glm::vec3& v) {
  return std::fmax(std::fabs(double(v.x)), std::fmax(std::fabs(double(v.y)), std::fabs(double(v.z))));
}

inline bool finite(const Affine& t) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(t.linear[c][r])) return false;
  return std::isfinite(t.offset.x) && std::isfinite(t.offset.y) && std::isfinite(t.offset.z);
}

}  // namespace lancer::two_level
