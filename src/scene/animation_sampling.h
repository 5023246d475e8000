// The value of one glTF animation channel at a time (glTF 2.0, "Animations" and Appendix C,
// "Interpolation"): keyframes in increasing time, held before the first and after the last.
// Pure arithmetic, so each mode is tested against values worked out by hand.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace lancer::gltf {

enum class Interpolation { Step, Linear, CubicSpline };

struct ChannelKeys {
  std::span<const float> times;  // strictly increasing, finite
  // `width` numbers per element (3: translation or scale, 4: rotation as x, y, z, w, the
  // morph target count: weights); one element per keyframe, or three for CubicSpline
  // (in-tangent, value, out-tangent).
  std::span<const double> values;
  std::size_t width = 0;
  Interpolation interpolation = Interpolation::Linear;
  bool rotation = false;  // unit quaternions: Linear is slerp, CubicSpline is normalised
};

// The channel's value at `time`: Step holds key k on [t_k, t_k+1); Linear interpolates (a
// rotation by slerp along the shorter arc); CubicSpline is the cubic Hermite spline through
// the values with the tangents scaled by the keyframe interval. Before the first keyframe
// the first value, after the last the last. The caller has checked the sizes.
std::vector<double> sample_channel(const ChannelKeys& keys, double time);

}  // namespace lancer::gltf
