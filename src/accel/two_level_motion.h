// Moving instances in the two-level accelerator (issue 19, motion blur): the checks their
// motions must pass, and their world boxes over the whole shutter. A moving instance is
// entered with ray_to_object(instance_at(geometry, inst, ray.time), ray); these boxes make
// the top level's error argument (two_level_ray.h) hold for every time at once.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "accel/instances.h"
#include "accel/triangle_soa.h"

namespace lancer::two_level {

// Throws std::invalid_argument unless every instance's motion is kNoHit or indexes
// geometry.motions, and every motion has at least two keys, all finite, with unit
// quaternions (within 2^-16 in squared length), stretches whose symmetric parts are all
// positive definite or all negative definite (proper or mirroring all the shutter long),
// each with eigenvalues within 2^44 of one another, and transforms within the static
// instances' limits (2^40 either way) at every key.
void validate_motions(const InstancedGeometry& geometry);

// What the top level needs of a moving instance: its box over the shutter, widened as
// two_level.cpp widens a static one, its beta, and a bound on the infinity norm of
// to_world.linear at any time (for the bottom trees' slack).
struct ShutterBounds {
  Bounds3 box;
  // The shutter cut into equal parts of [0, 1], each part's box widened alike: a ray whose
  // time falls in piece_of(pieces.size(), time) can only hit the instance inside it. Each
  // key interval is cut into the same number of parts, 16 at most, and halved until the
  // total is at most kMaxShutterPieces or each interval is one part.
  std::vector<Bounds3> pieces;
  double beta = 0.0;
  double linear_norm = 0.0;
};

inline constexpr std::size_t kMaxShutterPieces = 64;

// The piece of a shutter cut into `count` equal parts that holds `time` (clamped to [0, 1],
// NaN as 0, as instance_at clamps it).
inline std::size_t piece_of(std::size_t count, float time) {
  const double t = std::clamp(std::isnan(time) ? 0.0 : double(time), 0.0, 1.0);
  // Exact: t has 24 significant bits and count is small.
  return std::min(std::size_t(int(t * double(count))), count - 1);
}

// `inst` moves (inst.motion indexes geometry.motions, validated); `object` is its mesh's
// box. Throws std::invalid_argument when the box overflows float.
ShutterBounds shutter_bounds(const InstancedGeometry& geometry, const Instance& inst, const Bounds3& object);

}  // namespace lancer::two_level
