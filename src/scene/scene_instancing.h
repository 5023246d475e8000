// What readers need to store a mesh once and draw it through instances (Scene::instancing).
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include <glm/mat4x4.hpp>

#include "scene/scene.h"

namespace lancer {

// The largest condition number (Frobenius norms of L and L^-1 multiplied) of an instance's
// linear part: beyond it a float transform of the ray loses more than a flattened copy
// computed in double, and the reader draws that copy in world space instead.
inline constexpr double kMaxInstanceCondition = 1e6;

// The instance of mesh `mesh` drawn by the affine `world` (its last row is ignored), both
// directions rounded from double. Nothing when `world` is singular, not finite, worse
// conditioned than kMaxInstanceCondition, or scales by 2^38 or more either way.
std::optional<Instance> make_instance(std::uint32_t mesh, const glm::dmat4& world);

// The affine `world` (its last row ignored) as a motion key: its translation and the polar
// decomposition of its linear part (instances.h, MotionKey), found by Higham's iteration
// Q <- (Q + Q^-T) / 2. Nothing where make_instance refuses the matrix.
std::optional<MotionKey> motion_key(const glm::dmat4& world);

// Puts the scene's triangles in the order `order`, a permutation of 0..triangle_count()-1:
// triangle k becomes old triangle order[k], with its material, source id, flags and
// per-corner attributes. Throws std::invalid_argument when `order` is not a permutation.
void reorder_triangles(Scene& scene, std::span<const std::uint32_t> order);

}  // namespace lancer
