// A ray's constants for the top level of the two-level accelerator, and the one descent
// step that single rays and packets share. In double: the top level is a small part of the
// work, and double keeps the plane distances of any finite float ray finite and within
// 2^-50 of exact, so only the error bounds below need an argument.
//
// Why the top level cannot skip an instance that holds the answer. An instance's hit is
// the bottom tree's answer for r' = ray_to_object(inst, ray): a point q on a triangle of
// the mesh (inside its object box B) at parameter t* of r', reported as a t with
// |t - t*| <= 2^-16 (|t| + E / max|dir'|), E the mesh's extent and dir' = r'.dir
// (kd_traverse_setup.h), where max|dir'| >= max|dir| / L. The world ray's point at t*
// differs from to_world(q) only by the rounding of r' and of to_object (the inverse of
// to_world, rounded): with infinity norms, L = |to_world.linear|, R = |to_object.linear|,
// c = to_object.offset and u = 2^-24, by at most 6u L (R (|org| + t*|dir|) + 2|c|), and
// t*|dir| <= |org| + S where S bounds the world box's coordinates. So at t* the world ray
// passes within
//   alpha + beta |org|,  alpha = 2^-19 L (R S + 2|c|),  beta = 2^-18 L R
// (a factor 5 above the bound) of the instance's world box. The build widens each world
// box by alpha (two_level.cpp). Each ray is traversed as a "fat" ray:
// within eps = beta |org| of a split plane it visits both sides (plane distances widened
// by eps / |dir[axis]|); its range [tnear, tfar] is widened by t_slack(t) and it skips a
// cell only when its best t lies below the cell's entry by more than t_slack(entry), where
//   t_slack(t) = kTopRelativeSlack (|t| + max(E L) / max|dir|),
// the maximum over the instances, 16 times the bottom trees' own slack.
//
// Moving instances. At time t the instance is instance_at(t), whose to_object is the
// rounded inverse of the exact double transform rather than of the rounded to_world: one
// more u L R |x| in the bound above, inside its factor 5. The argument holds at t with
// that time's L, R, c and S, so it holds at every time with bounds over the shutter:
// S from the box over the shutter, and L, R, c from the keys (two_level_motion.cpp:
// rotation keeps 2-norms, a blend of stretches has 2-norm at most the largest key's and,
// their symmetric parts all definite of one sign, smallest singular value at least the
// smallest key's eigenvalue; sqrt(3) converts to infinity norms). alpha, beta and E L
// use those, so one fat ray serves every time.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "accel/kd_node.h"
#include "accel/ray.h"
#include "accel/triangle_soa.h"

namespace lancer::two_level {

// The bottom trees' error in t relative to the exact parameter (2^-16), with a wide margin.
inline constexpr double kTopRelativeSlack = 0x1p-12;
// Rounding of the double plane distances and box clipping (a few 2^-53), with a margin.
inline constexpr double kTopPlaneSlack = 0x1p-40;
// Rays beyond these magnitudes (or not finite) test every instance instead: the bound
// above assumes no overflow or underflow in ray_to_object (two_level.cpp keeps the
// transforms' norms within 2^40).
inline constexpr double kTopMaxOrigin = 0x1p60;
inline constexpr double kTopMinDir = 0x1p-60, kTopMaxDir = 0x1p60;

enum class TopPlan { Miss, Traverse, Scan };

// max and min for operands that are not NaN where they are used below (finite, or a range
// end that may be infinite): inline compares, where std::fmax and std::fmin are libm calls.
inline double larger(double a, double b) { return a > b ? a : b; }
inline double smaller(double a, double b) { return a < b ? a : b; }

// setup_top_ray sets plan, and the other fields only for TopPlan::Traverse (a packet sets up
// 64 lanes per call; most miss the top level).
struct TopRay {
  TopPlan plan;
  double org[3];
  double inv_dir[3];  // 0 on a parallel axis
  double slack[3];    // eps / |dir[axis]|: the fat ray's parameter margin at a plane (0 if parallel)
  double eps;         // the fat ray's radius
  double t_abs;       // t_slack's absolute part
  bool parallel[3];   // dir[axis] == 0
  bool negative[3];   // dir[axis] < 0: the right child comes first
  double tmin, tmax;  // the ray's range within the widened root box
};

// Below this a hit at t cannot come from a cell entered at `entry` (or later).
inline double lowest_hit_in_cell(const TopRay& tr, double entry) {
  return entry - std::fabs(entry) * kTopRelativeSlack - tr.t_abs;
}

// `beta` and `extent` (max E L) as above, the largest over the instances; `root` the union
// of the widened boxes.
inline void setup_top_ray(const Ray& ray, const Bounds3& root, double beta, double extent, TopRay& tr) {
  tr.plan = TopPlan::Scan;
  double org_norm = 0.0, dir_norm = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(ray.org[a]) || !std::isfinite(ray.dir[a])) return;
    org_norm = larger(org_norm, std::fabs(double(ray.org[a])));
    dir_norm = larger(dir_norm, std::fabs(double(ray.dir[a])));
  }
  if (std::isnan(ray.tnear) || std::isnan(ray.tfar) || org_norm > kTopMaxOrigin || dir_norm < kTopMinDir ||
      dir_norm > kTopMaxDir)
    return;
  tr.plan = TopPlan::Miss;
  if (root.empty()) return;

  const double eps = beta * org_norm;
  const double t_abs = kTopRelativeSlack * extent / dir_norm;
  double t0 = double(ray.tnear), t1 = double(ray.tfar);
  t0 -= std::fabs(t0) * kTopRelativeSlack + t_abs;  // a hit reported at tnear may lie just before it
  if (std::isfinite(t1)) t1 += std::fabs(t1) * kTopRelativeSlack + t_abs;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a];
    const double lo = double(root.lo[a]) - eps, hi = double(root.hi[a]) + eps;
    tr.org[a] = o;
    tr.parallel[a] = d == 0.0;
    tr.negative[a] = d < 0.0;
    if (tr.parallel[a]) {
      if (o < lo || o > hi) return;  // Miss
      tr.inv_dir[a] = 0.0;
      tr.slack[a] = 0.0;
      continue;
    }
    tr.inv_dir[a] = 1.0 / d;
    tr.slack[a] = eps * std::fabs(tr.inv_dir[a]);
    const double ta = (lo - o) * tr.inv_dir[a], tb = (hi - o) * tr.inv_dir[a];
    const double enter = smaller(ta, tb), leave = larger(ta, tb);  // no branch: the sign is not predictable
    t0 = larger(t0, enter - std::fabs(enter) * kTopPlaneSlack);
    t1 = smaller(t1, leave + std::fabs(leave) * kTopPlaneSlack);
  }
  if (!(t0 <= t1)) return;  // Miss
  tr.plan = TopPlan::Traverse;
  tr.eps = eps;
  tr.t_abs = t_abs;
  tr.tmin = t0;
  tr.tmax = t1;
}

inline TopRay setup_top_ray(const Ray& ray, const Bounds3& root, double beta, double extent) {
  TopRay tr{};
  setup_top_ray(ray, root, beta, extent, tr);
  return tr;
}

// A cheap first test, before setup_top_ray, for a ray whose tfar is finite (most often a
// hit already found in a direct instance): true only if setup_top_ray would answer Miss
// (false for any ray it would Scan).
// It needs no division: the points of the ray over setup_top_ray's widened range
// [tnear - d0, tfar + d1] lie within w = 2^-12 (max(|tnear|, |tfar|) max|dir| + extent) of
// the box of the segment's end points at tnear and tfar (d0 and d1 are at most
// 2^-12 (|t| + extent / max|dir|)); if that box, widened by w, misses the root widened by
// eps = beta |org| and by a margin far above the rounding of both computations (the end
// points' double rounding and the slab test's kTopPlaneSlack, both below 2^-39 of the
// magnitudes involved), some axis's slab interval misses the ray's range.
// The ray's segment box, widened as above, for testing against boxes whose coordinates are
// at most `box_norm` in magnitude. `usable` is false for the rays the argument leaves to
// setup_top_ray: not finite, an infinite tfar, or a ray setup_top_ray scans.
struct SegmentBox {
  bool usable = false;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};

  // No branches: a packet tests every lane, and whether a lane misses is not predictable.
  bool misses(const Bounds3& box) const {
    bool out = false;
    for (int a = 0; a < 3; ++a) out |= (lo[a] > double(box.hi[a])) | (hi[a] < double(box.lo[a]));
    return usable & out;
  }
};

inline SegmentBox segment_box(const Ray& ray, double beta, double extent, double box_norm) {
  SegmentBox sb;
  // x - x is NaN exactly when x is not finite.
  const double t0 = ray.tnear, t1 = ray.tfar;
  double org_norm = 0.0, dir_norm = 0.0, probe = (t0 - t0) + (t1 - t1);
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a];
    probe += (o - o) + (d - d);
    org_norm = larger(org_norm, std::fabs(o));
    dir_norm = larger(dir_norm, std::fabs(d));
  }
  sb.usable = (probe == 0.0) & (org_norm <= kTopMaxOrigin) & (dir_norm >= kTopMinDir) & (dir_norm <= kTopMaxDir) &
              (t0 <= t1);
  const double reach = larger(std::fabs(t0), std::fabs(t1)) * dir_norm;
  const double margin = 0x1p-12 * (reach + extent) + beta * org_norm + 0x1p-30 * (org_norm + reach + box_norm);
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a];
    const double p0 = o + t0 * d, p1 = o + t1 * d;
    sb.lo[a] = smaller(p0, p1) - margin;
    sb.hi[a] = larger(p0, p1) + margin;
  }
  return sb;
}

// The largest magnitude of the box's coordinates (segment_box's box_norm).
inline double box_norm(const Bounds3& box) {
  double n = 0.0;
  for (int a = 0; a < 3; ++a) n = larger(n, larger(std::fabs(double(box.lo[a])), std::fabs(double(box.hi[a]))));
  return n;
}

inline bool segment_misses(const Ray& ray, const Bounds3& root, double beta, double extent) {
  if (root.empty()) return segment_box(ray, beta, extent, 0.0).usable;
  return segment_box(ray, beta, extent, box_norm(root)).misses(root);
}

// Whether the fat ray can meet `box` (an instance's widened world box, the one the top
// level was built over) within its range [tmin, tmax]: setup_top_ray's clip against the
// root, made against one box, so it passes wherever the top level's argument lets a hit
// through. A lane that fails it need not enter a moving instance, whose transform at the
// lane's time costs an interpolation (instance_at).
inline bool fat_ray_meets_box(const TopRay& tr, const Bounds3& box) {
  double t0 = tr.tmin, t1 = tr.tmax;
  for (int a = 0; a < 3; ++a) {
    const double lo = double(box.lo[a]) - tr.eps, hi = double(box.hi[a]) + tr.eps;
    if (tr.parallel[a]) {
      if (tr.org[a] < lo || tr.org[a] > hi) return false;
      continue;
    }
    const double ta = (lo - tr.org[a]) * tr.inv_dir[a], tb = (hi - tr.org[a]) * tr.inv_dir[a];
    const double enter = smaller(ta, tb), leave = larger(ta, tb);
    t0 = larger(t0, enter - std::fabs(enter) * kTopPlaneSlack);
    t1 = smaller(t1, leave + std::fabs(leave) * kTopPlaneSlack);
  }
  return t0 <= t1;
}

// Which children of inner node (axis, split) the fat ray needs over [tmin, tmax]: the near
// one (left unless `negative`, which must be the ray's own sign unless it is parallel) over
// [tmin, near_max], the far one over [far_min, tmax]. A ray parallel to the plane keeps its
// interval on each side it reaches.
struct TopStep {
  bool near, far;
  double near_max, far_min;
};

inline TopStep top_step(const TopRay& tr, int axis, float split, bool negative, double tmin, double tmax) {
  const double p = split;
  if (tr.parallel[axis]) {
    const bool left = tr.org[axis] - tr.eps <= p, right = tr.org[axis] + tr.eps >= p;
    return {negative ? right : left, negative ? left : right, tmax, tmin};
  }
  const double tp = (p - tr.org[axis]) * tr.inv_dir[axis];
  const double s = tr.slack[axis] + std::fabs(tp) * kTopPlaneSlack;
  return {tmin <= tp + s, tp - s <= tmax, smaller(tmax, tp + s), larger(tmin, tp - s)};
}

// The instances a ray (or which lanes of a packet) entered lately. An instance straddling
// several leaves is met again in each; entering it again cannot change the answer (its
// bottom tree answers the same, and tfar has only narrowed since: the best so far only
// decreases in (t, instance) order), so the lanes that entered it already skip it. A large
// instance under many small ones (a floor) would otherwise be traversed once per leaf.
class Mailbox {
 public:
  // The lanes of `lanes` that have not entered instance i lately; records them as entering.
  std::uint64_t enter(std::uint32_t i, std::uint64_t lanes) {
    for (int k = 0; k < kSize; ++k)
      if (id_[k] == i) lanes &= ~lanes_[k];
    if (lanes != 0) {
      id_[next_] = i;
      lanes_[next_] = lanes;
      next_ = (next_ + 1) % kSize;
    }
    return lanes;
  }

 private:
  static constexpr int kSize = 8;
  std::uint32_t id_[kSize] = {kNoHit, kNoHit, kNoHit, kNoHit, kNoHit, kNoHit, kNoHit, kNoHit};
  std::uint64_t lanes_[kSize] = {};
  int next_ = 0;
};

}  // namespace lancer::two_level
