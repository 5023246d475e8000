// glTF alpha coverage (material.alphaMode) for every integrator.
//
// The glTF 2.0 spec ("Alpha Coverage"): alpha = baseColorFactor.a * baseColorTexture.a *
// COLOR_0.a; OPAQUE ignores it, MASK renders the surface fully opaque where alpha >=
// alphaCutoff and fully transparent elsewhere, BLEND composites it over what lies behind
// with the "over" operator, i.e. the surface covers the fraction alpha of the point. A ray
// tracer reads that as coverage (evaluate_shading's alpha, surface_coverage): at a hit the
// surface is there with probability alpha, and otherwise the ray goes on unchanged, as if
// the triangle were not there.
//  - Camera and scattered rays: the path tracer picks one or the other per hit (MASK needs
//    no random number); Whitted follows both, weighted alpha and 1 - alpha; the debug views
//    see through a surface where its coverage is 0.
//  - Shadow rays (and ambient-occlusion probes) let through the product of (1 - alpha) over
//    the surfaces they cross: shadow_transmittance, exact rather than sampled.
//  - An emissive surface emits alpha times its radiance (light sampling included).
// The back side of a single-sided material (culls_back_faces in render/shading_inputs.h)
// has coverage 0 for every ray: the ray goes on past it, its shadow is not cast, its
// emission not seen. A scene whose materials are all OPAQUE and double-sided never pays
// for any of it (scene_has_coverage).
#pragma once

#include <cstdint>

#include "accel/accelerator.h"
#include "accel/ray.h"
#include "scene/scene.h"

namespace lancer {

// Surfaces crossed by one ray at most. Each crossing moves past a triangle that cannot be
// hit again, so a ray ends anyway; the bound only keeps a pathological stack of cut-outs
// from costing more than this many traces (or recursion levels) per ray. Beyond it a
// shadow ray counts as blocked and other rays stop at the surface they reached.
inline constexpr int kMaxCrossings = 1024;

// Whether any triangle of `scene` has a MASK, BLEND or back-face-culling material.
bool scene_has_coverage(const Scene& scene);

// `ray` continued past the triangle of its valid hit `hit`: the same direction, from just
// beyond the triangle (ray_offset.h, so the triangle cannot be hit again), up to the same
// end point when tfar is finite.
Ray continue_past(const Scene& scene, const Ray& ray, const Hit& hit);

// Moves `hit`, the closest hit of `ray`, past the surfaces of coverage 0 (MASK cut-outs,
// BLEND alpha 0) to the first one with some coverage along `ray`, or to none; its t is
// still measured along `ray`.
void skip_uncovered(const Scene& scene, const Accelerator& accel, const Ray& ray, Hit& hit, std::uint64_t& rays);

// The fraction of light `shadow` lets through: 1 when nothing lies on it (`occluded` is the
// accelerator's own answer for it), 0 when an opaque surface does, else the product of
// 1 - coverage over the surfaces it crosses. `rays` counts the extra rays traced.
float shadow_transmittance(const Scene& scene, const Accelerator& accel, const Ray& shadow, bool occluded,
                           std::uint64_t& rays);

// One shadow ray traced and answered: 0 or 1 by the accelerator's occlusion test alone
// when `has_coverage` is false (scene_has_coverage), else its transmittance. `rays` counts
// every ray traced, this one included.
float shadow_visibility(const Scene& scene, const Accelerator& accel, const Ray& shadow, bool has_coverage,
                        std::uint64_t& rays);

}  // namespace lancer
