// The generic (ISA-independent) parts of single-ray kd-tree traversal, compiled once in
// kd_traverse.cpp and called by every per-ISA kernel: per-ray setup, the scan fallback and
// the exact scalar test of one leaf slot. Plain data and declarations only: an inline
// function here would be compiled again with each ISA's flags (the ODR trap, STYLE.md).
// The exactness argument these serve is in kd_traverse-inl.h.
#pragma once

#include <cstdint>

#include "accel/kd_traverse.h"
#include "accel/ray.h"

namespace lancer {

// Cell intervals are widened by slack(t) = |t| * kKdRelativeSlack + abs_slack.
//   2^-16 (256 float ulps of t) covers the watertight kernel's error in t; 2^-20 covers the
//   rounding of the float plane distances and interval arithmetic (a few 2^-24 each).
inline constexpr double kKdRelativeSlack = 0x1p-16 + 0x1p-20;
//   abs_slack = kKdExtentSlack * (largest scene extent) / max|dir|.
inline constexpr double kKdExtentSlack = 0x1p-16;

enum class KdPlan { Miss, Traverse, Scan };

// Per-ray constants of the traversal, in double; `float_ok` says the float copies are safe
// (every plane distance, slack and interval bound of this ray stays within [2^-100, 2^66]
// in magnitude or is exactly 0, so float arithmetic neither overflows nor loses the slack).
struct KdRaySetup {
  KdPlan plan;
  bool float_ok;
  bool parallel[3];  // dir[axis] == 0: never crosses a plane of that axis
  bool negative[3];  // dir[axis] < 0: the right child comes first
  double inv_dir[3];
  double abs_slack;
  double t0, t1;  // the ray range clipped to the scene box, both widened by the slack
  // Float copies: t0 rounded down and t1 up; inv_dir and abs_slack to nearest (2^-24
  // relative, within the 2^-20 term).
  float inv_dir_f[3];
  float abs_slack_f;
  float t0_f, t1_f;
};

// Tries kd_setup_ray_float first; the rays it declines are set up in double.
KdRaySetup kd_setup_ray(const KdTreeView& tree, const Ray& ray);

// The double path alone, for rays a float setup has already declined (the kernels' own
// width-1 or vector setup): every ray gets a plan (Miss, Scan or Traverse).
KdRaySetup kd_setup_ray_double(const KdTreeView& tree, const Ray& ray);

// kd_setup_ray's common case in float: the width-generic setup of kd_ray_setup-inl.h at
// width 1, as lancer::scalar compiles it (each ISA's kernels call their own copy): sets s
// (plan Traverse with float_ok, or Miss) and returns true for a ray within its limits
// (finite, every direction component at least 2^-60, moderate magnitudes); returns false
// with s untouched for any other ray. Its float interval differs from the double path's
// by float rounding, which the 2^-20 term of kKdRelativeSlack absorbs, so the hits are the
// oracle's either way.
bool kd_setup_ray_float(const KdTreeView& tree, const Ray& ray, KdRaySetup& s);

// The largest extent of the box, rounded up to a float (the slack must not shrink): E in
// the float setups' abs_slack = kKdExtentSlack * E / max|dir|.
float kd_max_extent_up(const Bounds3& b);

// Every leaf slot with the oracle's rule (exact by construction, O(references)).
Hit kd_scan_intersect(const KdTreeView& tree, const Ray& ray);
bool kd_scan_occluded(const KdTreeView& tree, const Ray& ray);

// The oracle's scalar watertight kernel on one leaf slot (with its double-precision
// recomputation of zero edge functions): true and t, u, v when hit with tnear <= t < limit.
// Vector kernels call it for the rare lanes where an edge function is exactly 0.
bool kd_slot_hit(const KdTreeView& tree, const Ray& ray, std::uint32_t slot, float limit, float out_tuv[3]);

}  // namespace lancer
