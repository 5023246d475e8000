#include "scene/animation_sampling.h"

#include <algorithm>
#include <cmath>

namespace lancer::gltf {

namespace {

// Element `e` of keyframe `k`: for CubicSpline e is 0 (in-tangent), 1 (value), 2 (out-tangent).
const double* element(const ChannelKeys& keys, std::size_t k, std::size_t e) {
  const std::size_t per_key = keys.interpolation == Interpolation::CubicSpline ? 3 : 1;
  return keys.values.data() + (k * per_key + e) * keys.width;
}

std::vector<double> value_of(const ChannelKeys& keys, std::size_t k) {
  const double* v = element(keys, k, keys.interpolation == Interpolation::CubicSpline ? 1 : 0);
  return {v, v + keys.width};
}

void normalise(std::vector<double>& q) {
  double n = 0.0;
  for (double x : q) n += x * x;
  n = std::sqrt(n);
  if (n > 0.0)
    for (double& x : q) x /= n;
}

// Spherical linear interpolation of unit quaternions a and b (Shoemake 1985), along the
// shorter arc: q and -q are one rotation.
std::vector<double> slerp(const double* a, const double* b, double s) {
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double sign = d < 0.0 ? -1.0 : 1.0;
  d = std::min(std::abs(d), 1.0);
  double wa = 1.0 - s, wb = s;
  if (d < 1.0 - 1e-9) {  // (nearly equal: the linear weights, then normalised)
    const double angle = std::acos(d), sin_angle = std::sin(angle);
    wa = std::sin((1.0 - s) * angle) / sin_angle;
    wb = std::sin(s * angle) / sin_angle;
  }
  std::vector<double> q(4);
  for (int i = 0; i < 4; ++i) q[i] = wa * a[i] + wb * sign * b[i];
  normalise(q);
  return q;
}

}  // namespace

std::vector<double> sample_channel(const ChannelKeys& keys, double time) {
  const std::size_t n = keys.times.size();
  if (n == 1 || time <= keys.times[0]) return value_of(keys, 0);
  if (time >= keys.times[n - 1]) return value_of(keys, n - 1);
  // Key k with t_k <= time < t_k+1.
  const std::size_t k =
      static_cast<std::size_t>(std::upper_bound(keys.times.begin(), keys.times.end(), time) - keys.times.begin()) - 1;
  const double t0 = keys.times[k], t1 = keys.times[k + 1], dt = t1 - t0;
  const double s = (time - t0) / dt;
  const std::size_t w = keys.width;
  std::vector<double> out(w);
  switch (keys.interpolation) {
    case Interpolation::Step: return value_of(keys, k);
    case Interpolation::Linear: {
      const double *a = element(keys, k, 0), *b = element(keys, k + 1, 0);
      if (keys.rotation) return slerp(a, b, s);
      for (std::size_t i = 0; i < w; ++i) out[i] = (1.0 - s) * a[i] + s * b[i];
      return out;
    }
    case Interpolation::CubicSpline: {
      // glTF Appendix C: p(s) = (2s^3 - 3s^2 + 1) v_k + dt (s^3 - 2s^2 + s) b_k
      //                        + (-2s^3 + 3s^2) v_k+1 + dt (s^3 - s^2) a_k+1,
      // with b_k the out-tangent of key k and a_k+1 the in-tangent of key k+1.
      const double s2 = s * s, s3 = s2 * s;
      const double *v0 = element(keys, k, 1), *b0 = element(keys, k, 2);
      const double *v1 = element(keys, k + 1, 1), *a1 = element(keys, k + 1, 0);
      for (std::size_t i = 0; i < w; ++i)
        out[i] = (2 * s3 - 3 * s2 + 1) * v0[i] + dt * (s3 - 2 * s2 + s) * b0[i] + (-2 * s3 + 3 * s2) * v1[i] +
                 dt * (s3 - s2) * a1[i];
      if (keys.rotation) normalise(out);
      return out;
    }
  }
  return out;
}

}  // namespace lancer::gltf
