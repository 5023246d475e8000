#include "accel/two_level_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "accel/two_level_norms.h"

namespace lancer::two_level {

namespace {

// Samples of the transform per key interval for the shutter box.
constexpr int kSamplesPerKey = 16;
// Interpolated transforms may exceed the keys' 2^40 by the factors below (sqrt(3), the
// symmetric part's eigenvalues); past this the no-overflow premise of two_level_ray.h is
// no longer safe.
constexpr double kMaxBlendNorm = 0x1p42;

// Eigenvalues of the symmetric matrix a (row-major), by cyclic Jacobi rotations (Golub &
// Van Loan, "Matrix Computations", 8.5): each rotation zeroes one off-diagonal pair and
// keeps the eigenvalues; the off-diagonal mass falls quadratically, so a few sweeps reach
// rounding level (absolute error a few 2^-52 of the largest eigenvalue).
void symmetric_eigenvalues(double a[3][3], double out[3]) {
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (!(off > 0x1p-110 * diag)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a J
          const double kp = a[k][p], kq = a[k][q];
          a[k][p] = c * kp - s * kq;
          a[k][q] = s * kp + c * kq;
        }
        for (int k = 0; k < 3; ++k) {  // J^T a
          const double pk = a[p][k], qk = a[q][k];
          a[p][k] = c * pk - s * qk;
          a[q][k] = s * pk + c * qk;
        }
      }
  }
  for (int k = 0; k < 3; ++k) out[k] = a[k][k];
}

// The signed eigenvalue of the stretch's symmetric part nearest zero, moved towards zero
// by more than Jacobi's error (measured below 2^-48 of the largest), or 0 when that part
// is not definite (eigenvalues of both signs, or one within 2^-44 of the largest).
double definite_part(const glm::mat3& stretch) {
  double h[3][3], e[3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) h[r][c] = 0.5 * (double(stretch[c][r]) + double(stretch[r][c]));
  symmetric_eigenvalues(h, e);
  const double lo = std::fmin(e[0], std::fmin(e[1], e[2])), hi = std::fmax(e[0], std::fmax(e[1], e[2]));
  const double largest = std::fmax(std::fabs(lo), std::fabs(hi)), slack = 0x1p-44 * largest;
  if (lo > 2.0 * slack) return lo - slack;
  if (hi < -2.0 * slack) return hi + slack;
  return 0.0;
}

// |m|_2 <= sqrt(|m|_1 |m|_inf), for any matrix.
double norm2_bound(const glm::dmat3& m) {
  return std::sqrt(norm_inf(glm::transpose(m)) * norm_inf(m));
}

bool finite(const MotionKey& k) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(k.stretch[c][r])) return false;
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(k.rotation[c])) return false;
  return std::isfinite(k.translation.x) && std::isfinite(k.translation.y) && std::isfinite(k.translation.z);
}

// Bounds over the whole shutter of a validated motion, in the infinity norms of
// two_level_ray.h: l >= |to_world.linear|, r >= |to_object.linear|, c >= |to_object.offset|
// at any time, t >= |translation|; sigma >= |stretch|_2.
struct MotionNorms {
  double l = 0.0, r = 0.0, c = 0.0, t = 0.0, sigma = 0.0;
};

// Why these bound every time, not only the keys. At time t, to_world.linear is
// rotation * stretch, stretch = (1 - f) A + f B for neighbouring keys A, B. Rotation keeps
// 2-norms, and the 2-norm is convex, so |linear|_2 <= max |stretch_k|_2 =: sigma. For the
// inverse: with H the symmetric part of a stretch, x^T S x = x^T H x, so |S x| >= |x^T S x|
// >= lambda |x| when H is definite with smallest |eigenvalue| lambda; the blend's x^T S x
// is the blend of the keys' (all of one sign: validated), so |linear^-1|_2 <= 1 / min
// lambda_k. The infinity norm is at most sqrt(3) times the 2-norm; 2^-20 covers rounding
// the double transforms to float.
MotionNorms motion_norms(const InstanceMotion& motion) {
  MotionNorms n;
  double lambda = kInfinity;
  for (const MotionKey& k : motion.keys) {
    n.sigma = std::fmax(n.sigma, norm2_bound(glm::dmat3(k.stretch)));
    lambda = std::fmin(lambda, std::fabs(definite_part(k.stretch)));
    n.t = std::fmax(n.t, norm_inf(k.translation));
  }
  const double round = 1.0 + 0x1p-20;
  n.l = std::sqrt(3.0) * n.sigma * round;
  n.r = std::sqrt(3.0) / lambda * round;
  n.c = n.r * n.t * round;
  return n;
}

}  // namespace

void validate_motions(const InstancedGeometry& geometry) {
  for (std::size_t i = 0; i < geometry.instances.size(); ++i) {
    const std::uint32_t m = geometry.instances[i].motion;
    if (m != kNoHit && m >= geometry.motions.size())
      throw std::invalid_argument("two-level: instance " + std::to_string(i) + " uses motion " + std::to_string(m) +
                                  " of " + std::to_string(geometry.motions.size()));
  }
  for (std::size_t m = 0; m < geometry.motions.size(); ++m) {
    const std::vector<MotionKey>& keys = geometry.motions[m].keys;
    const std::string which = "two-level: motion " + std::to_string(m);
    if (keys.size() < 2)
      throw std::invalid_argument(which + " has " + std::to_string(keys.size()) + " keys; it needs at least 2");
    double sign = 0.0;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      const MotionKey& key = keys[k];
      const std::string at = which + " key " + std::to_string(k);
      if (!finite(key)) throw std::invalid_argument(at + " is not finite");
      const double q2 = glm::dot(glm::dquat(key.rotation), glm::dquat(key.rotation));
      if (!(std::fabs(q2 - 1.0) <= 0x1p-16)) throw std::invalid_argument(at + ": the rotation is not a unit quaternion");
      const double lambda = definite_part(key.stretch);
      if (lambda == 0.0)
        throw std::invalid_argument(at + ": the stretch is not definite, or nearly singular (a polar "
                                         "decomposition's is positive definite, or negative definite for a "
                                         "mirroring transform)");
      if (sign != 0.0 && (lambda > 0.0) != (sign > 0.0))
        throw std::invalid_argument(at + ": the stretch turns between mirroring and proper; the blend of the keys "
                                         "passes through a singular transform");
      sign = lambda;
      const Instance inst = instance_from_key(0, key);
      if (!finite(inst.to_world) || !finite(inst.to_object))
        throw std::invalid_argument(at + " has a transform that is not finite");
      const double l = norm_inf(inst.to_world.linear), r = norm_inf(inst.to_object.linear);
      if (!(l > 0.0) || !(r > 0.0) || l > kMaxNorm || r > kMaxNorm)
        throw std::invalid_argument(at + " has a singular transform or one scaling by more than 2^40");
    }
    const MotionNorms n = motion_norms(geometry.motions[m]);
    if (!(n.l <= kMaxBlendNorm) || !(n.r <= kMaxBlendNorm))
      throw std::invalid_argument(which + " may scale by more than 2^42 between its keys");
  }
}

// The box: every key interval sampled at kSamplesPerKey + 1 times through instance_at
// itself (the float transforms the traversal uses), the object box's corners moved by
// each; a transform is affine in the point, so the mesh at any time lies in the hull of
// the corners then, and it suffices to bound each corner's path between two samples.
//
// Within a key interval the path of corner p is g(f) = Q(f) S(f) p + T(f): S and T linear
// in f, Q(f) = Q(f0) rotated about one fixed axis by an angle growing like (f - f0) theta
// (slerp; theta the keys' rotation angle). Not linear, so the chord between samples does
// not hold it, but |g''| <= phi^2 |S p| + 2 phi |S' p| per unit of the sub-interval (phi =
// theta h the angle swept in it, h its length in f, S' p = h (B - A) p), and a C^2 path
// strays from its chord by at most max |g''| / 8 per coordinate: the arc's bulge
// r (1 - cos(phi / 2)) ~ r phi^2 / 8 plus the stretch turning with the rotation. Also
// covered: the slerp's speed is only nearly uniform (keys a few ulps off unit length; the
// normalised lerp used below 1.6 degrees): delta = 2^-12 theta + theta^3 of angle, twice;
// a sample a few ulps of time off a key (kink, bounded by the path's speed); and rounding
// the transforms to float (2^-20 of the largest coordinate they can produce).
ShutterBounds shutter_bounds(const InstancedGeometry& geometry, const Instance& inst, const Bounds3& object) {
  const std::vector<MotionKey>& keys = geometry.motions[inst.motion].keys;
  const MotionNorms n = motion_norms(geometry.motions[inst.motion]);
  ShutterBounds out;
  out.beta = 0x1p-18 * n.l * n.r;
  out.linear_norm = n.l;
  if (object.empty()) return out;

  glm::dvec3 corners[8];
  double p2 = 0.0, p_inf = 0.0;
  for (int c = 0; c < 8; ++c) {
    corners[c] = glm::dvec3((c & 1 ? object.hi : object.lo).x, (c & 2 ? object.hi : object.lo).y,
                            (c & 4 ? object.hi : object.lo).z);
    p2 = std::fmax(p2, glm::length(corners[c]));
    for (int a = 0; a < 3; ++a) p_inf = std::fmax(p_inf, std::fabs(corners[c][a]));
  }
  const std::size_t intervals = keys.size() - 1;
  const double samples = double(kSamplesPerKey) * double(intervals);
  const double h = 1.0 / kSamplesPerKey + double(intervals) * 0x1p-22;  // float times are a little uneven
  glm::dvec3 lo(kInfinity), hi(-kInfinity);
  // Per sample m (time float(m / samples)), the box of the corners then.
  const std::size_t sample_count = std::size_t(kSamplesPerKey) * intervals + 1;
  std::vector<glm::dvec3> sample_lo(sample_count, glm::dvec3(kInfinity)), sample_hi(sample_count, glm::dvec3(-kInfinity));
  double stray = 0.0;
  for (std::size_t i = 0; i < intervals; ++i) {
    for (int j = i == 0 ? 0 : 1; j <= kSamplesPerKey; ++j) {  // an inner key: the interval before sampled it
      const std::size_t m = i * kSamplesPerKey + std::size_t(j);
      const float time = float(double(m) / samples);
      const Instance at = instance_at(geometry, inst, time);
      const glm::dmat3 mat(at.to_world.linear);
      const glm::dvec3 b(at.to_world.offset);
      for (const glm::dvec3& p : corners) {
        const glm::dvec3 w = mat * p + b;
        sample_lo[m] = glm::min(sample_lo[m], w);
        sample_hi[m] = glm::max(sample_hi[m], w);
      }
      lo = glm::min(lo, sample_lo[m]);
      hi = glm::max(hi, sample_hi[m]);
    }
    const glm::dquat qa(keys[i].rotation), qb(keys[i + 1].rotation);
    const double cos_half = std::fabs(glm::dot(qa, qb)) / std::sqrt(glm::dot(qa, qa) * glm::dot(qb, qb));
    const double theta = 2.0 * std::acos(std::fmin(1.0, cos_half));
    const double phi = theta * h;
    const double d = norm2_bound(glm::dmat3(keys[i + 1].stretch) - glm::dmat3(keys[i].stretch));
    const double delta = 0x1p-12 * theta + (theta < 0.1 ? theta * theta * theta : 0.0);
    stray = std::fmax(stray, (phi * phi * n.sigma + 2.0 * phi * h * d) / 8.0 * p2 + 2.0 * delta * n.sigma * p2);
  }
  // A sample meant for an inner key may land up to intervals 2^-25 of f beside it; the path
  // moves at most 6 sigma |p| + 4 |T| per unit of f.
  const double kink = intervals > 1 ? double(intervals) * 0x1p-24 * (6.0 * n.sigma * p2 + 4.0 * n.t) : 0.0;
  const double rounding = 0x1p-20 * (n.l * p_inf + n.t);
  const double path = stray + kink + rounding;
  lo -= path;
  hi += path;
  double s = 0.0;
  for (int a = 0; a < 3; ++a) s = std::fmax(s, std::fmax(std::fabs(lo[a]), std::fabs(hi[a])));
  // alpha (two_level_ray.h) with the worst norms over the shutter, then rounding to float.
  const double alpha = 0x1p-19 * n.l * (n.r * s + 2.0 * n.c);
  const double margin = alpha + 0x1p-20 * s;
  out.box.lo = glm::vec3(lo - margin);
  out.box.hi = glm::vec3(hi + margin);
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(out.box.lo[a]) || !std::isfinite(out.box.hi[a]))
      throw std::invalid_argument("two-level: a moving instance's world bounds overflow float");
  // Each piece's box: the samples from its start to its end, widened by the same margins,
  // which are maxima over the sub-intervals between samples (the stray and kink of any, alpha
  // of the whole box), so each holds its piece as the whole box holds the shutter; never
  // beyond the whole box. Why the piece piece_of names holds a time t: with P pieces of
  // `step` samples each, p = floor(t P) gives p step <= t samples < (p + 1) step exactly, and
  // rounding to float is monotone, so t lies between the piece's first and last sample
  // times (float(m / samples), as sampled above).
  std::size_t per_interval = kSamplesPerKey;
  while (per_interval > 1 && intervals * per_interval > kMaxShutterPieces) per_interval /= 2;
  const std::size_t step = kSamplesPerKey / per_interval;
  out.pieces.resize(intervals * per_interval);
  for (std::size_t p = 0; p < out.pieces.size(); ++p) {
    glm::dvec3 piece_lo(kInfinity), piece_hi(-kInfinity);
    for (std::size_t m = p * step; m <= (p + 1) * step; ++m) {
      piece_lo = glm::min(piece_lo, sample_lo[m]);
      piece_hi = glm::max(piece_hi, sample_hi[m]);
    }
    out.pieces[p].lo = glm::max(glm::vec3(piece_lo - path - margin), out.box.lo);
    out.pieces[p].hi = glm::min(glm::vec3(piece_hi + path + margin), out.box.hi);
  }
  return out;
}

}  // namespace lancer::two_level
