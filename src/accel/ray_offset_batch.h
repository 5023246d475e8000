// Ray origins for many rays at once: exactly what SurfaceOffset::origin and origin_towards
// give, bit for bit, with the bound of ray_offset.h evaluated for several rays per vector
// (ray_offset_batch-inl.h, one solver per ISA). A path tracer's bounce asks for two origins
// per hit (the continuation ray and a shadow ray); one at a time, the bound's double
// arithmetic over three vertices and three edges was a sixth of a render.
//
// The split: generic code (ray_offset_batch.cpp) lays each ray out as a lane (its triangle,
// point, normal and target; a triangle drawn through an instance is solved at once); the ISA
// solver makes each lane's plane and start as SurfaceOffset's make_plane() and start() do
// (the side, the deficit, the first height), then runs the attempts for every lane that
// stays on the common path (a triangle with area, one shear permutation, a bound that is
// finite and not near tangent, at most kBatchAttempts tries); every other lane is left to
// SurfaceOffset itself, which then gives the same answer.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "accel/ray_offset.h"
#include "simd/isa.h"

namespace lancer {

// One origin to find: leave->origin(target), or leave->origin_towards(target) when towards.
struct OriginRequest {
  const SurfaceOffset* leave = nullptr;
  glm::vec3 target{0.0f};
  bool towards = false;
};

// origins[i] = the origin requests[i] asks for, for i in [0, count), with the solver of
// `isa`; every ISA gives the same origins. Returns how many requests went to the scalar
// solver (the tests check that both paths are taken).
int solve_origins(const OriginRequest* requests, glm::vec3* origins, int count, Isa isa);
// The same with the best ISA this CPU runs, chosen once (the renderer calls it per bounce).
int solve_origins(const OriginRequest* requests, glm::vec3* origins, int count);

namespace ray_offset_batch {

inline constexpr int kMaxLanes = 64;  // lanes per solver call (a multiple of every vector width)
static_assert(kMaxLanes % 8 == 0);
inline constexpr int kBatchAttempts = 16;  // tries before a lane goes to the scalar solver

// Constants of the bound, as ray_offset.h computes them.
inline constexpr double kGamma1 = ray_offset_detail::gamma(1);
inline constexpr double kGamma2 = ray_offset_detail::gamma(2);
inline constexpr double kGamma3 = ray_offset_detail::gamma(3);
inline constexpr double kSubnormalError = ray_offset_detail::kSubnormalError;

// The lanes of one call, structure of arrays: SurfaceOffset's inputs and the ray's target;
// the solver makes the plane and the first attempt from them (SurfaceOffset::plane, start).
struct Lanes {
  alignas(64) float tri[9][kMaxLanes];  // vertex i, axis k at [3 i + k]
  alignas(64) float p[3][kMaxLanes];
  alignas(64) float n[3][kMaxLanes];       // the normal the caller gave: the side for a ray in the plane
  alignas(64) float target[3][kMaxLanes];  // the direction, or the segment's end
  alignas(64) std::int32_t towards[kMaxLanes];  // 1: target is an end point
};

// Solves lanes [0, count) (count <= kMaxLanes): origin i into out[.][i] and bit i of the
// result set, or bit i clear for a lane left to the scalar solver. Lanes up to the next
// multiple of 8 are set (copies of lane 0) and may be read.
using SolveLanesFn = std::uint64_t (*)(const Lanes& lanes, int count, float out[3][kMaxLanes]);

}  // namespace ray_offset_batch
}  // namespace lancer
