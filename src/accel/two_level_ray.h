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

struct TopRay {
  TopPlan plan = TopPlan::Miss;
  double org[3] = {0, 0, 0};
  double inv_dir[3] = {0, 0, 0};
  double slack[3] = {0, 0, 0};  // eps / |dir[axis]|: the fat ray's parameter margin at a plane
  double eps = 0.0;             // the fat ray's radius
  double t_abs = 0.0;           // t_slack's absolute part
  bool parallel[3] = {false, false, false};  // dir[axis] == 0
  bool negative[3] = {false, false, false};  // dir[axis] < 0: the right child comes first
  double tmin = 0.0, tmax = 0.0;             // the ray's range within the widened root box
};

// Below this a hit at t cannot come from a cell entered at `entry` (or later).
inline double lowest_hit_in_cell(const TopRay& tr, double entry) {
  return entry - std::fabs(entry) * kTopRelativeSlack - tr.t_abs;
}

// `beta` and `extent` (max E L) as above, the largest over the instances; `root` the union
// of the widened boxes.
inline TopRay setup_top_ray(const Ray& ray, const Bounds3& root, double beta, double extent) {
  TopRay tr;
  double org_norm = 0.0, dir_norm = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(ray.org[a]) || !std::isfinite(ray.dir[a])) {
      tr.plan = TopPlan::Scan;
      return tr;
    }
    org_norm = std::fmax(org_norm, std::fabs(double(ray.org[a])));
    dir_norm = std::fmax(dir_norm, std::fabs(double(ray.dir[a])));
  }
  if (std::isnan(ray.tnear) || std::isnan(ray.tfar) || org_norm > kTopMaxOrigin || dir_norm < kTopMinDir ||
      dir_norm > kTopMaxDir) {
    tr.plan = TopPlan::Scan;
    return tr;
  }
  if (root.empty()) return tr;  // Miss

  tr.eps = beta * org_norm;
  tr.t_abs = kTopRelativeSlack * extent / dir_norm;
  double t0 = double(ray.tnear), t1 = double(ray.tfar);
  t0 -= std::fabs(t0) * kTopRelativeSlack + tr.t_abs;  // a hit reported at tnear may lie just before it
  if (std::isfinite(t1)) t1 += std::fabs(t1) * kTopRelativeSlack + tr.t_abs;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a];
    const double lo = double(root.lo[a]) - tr.eps, hi = double(root.hi[a]) + tr.eps;
    tr.org[a] = o;
    tr.parallel[a] = d == 0.0;
    tr.negative[a] = d < 0.0;
    if (tr.parallel[a]) {
      if (o < lo || o > hi) return tr;  // Miss
      continue;
    }
    tr.inv_dir[a] = 1.0 / d;
    tr.slack[a] = tr.eps * std::fabs(tr.inv_dir[a]);
    double ta = (lo - o) * tr.inv_dir[a], tb = (hi - o) * tr.inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::fmax(t0, ta - std::fabs(ta) * kTopPlaneSlack);
    t1 = std::fmin(t1, tb + std::fabs(tb) * kTopPlaneSlack);
  }
  if (!(t0 <= t1)) return tr;  // Miss
  tr.plan = TopPlan::Traverse;
  tr.tmin = t0;
  tr.tmax = t1;
  return tr;
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
    double ta = (lo - tr.org[a]) * tr.inv_dir[a], tb = (hi - tr.org[a]) * tr.inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::fmax(t0, ta - std::fabs(ta) * kTopPlaneSlack);
    t1 = std::fmin(t1, tb + std::fabs(tb) * kTopPlaneSlack);
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
  return {tmin <= tp + s, tp - s <= tmax, std::fmin(tmax, tp + s), std::fmax(tmin, tp - s)};
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
