// One glTF animation channel at a time, each interpolation against values worked out by
// hand (glTF 2.0 Appendix C): STEP holds, LINEAR interpolates (rotations by slerp on the
// shorter arc), CUBICSPLINE follows the Hermite spline with tangents scaled by the
// keyframe interval; every mode holds its first value before the first keyframe and its
// last after the last.
#include "scene/animation_sampling.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace lancer::gltf {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<double> at(const std::vector<float>& times, const std::vector<double>& values, std::size_t width,
                       Interpolation mode, double t, bool rotation = false) {
  ChannelKeys keys;
  keys.times = times;
  keys.values = values;
  keys.width = width;
  keys.interpolation = mode;
  keys.rotation = rotation;
  return sample_channel(keys, t);
}

void expect_near(const std::vector<double>& got, const std::vector<double>& want, double tol = 1e-12) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], tol) << "element " << i;
}

TEST(AnimationSampling, StepHoldsEachKeyUntilTheNext) {
  const std::vector<float> t = {0.0f, 1.0f, 2.0f};
  const std::vector<double> v = {10, 20, 30};
  for (const auto& [time, want] : std::vector<std::pair<double, double>>{
           {-1.0, 10}, {0.0, 10}, {0.5, 10}, {0.999, 10}, {1.0, 20}, {1.999, 20}, {2.0, 30}, {7.0, 30}})
    expect_near(at(t, v, 1, Interpolation::Step, time), {want});
}

TEST(AnimationSampling, LinearTranslationAndWeights) {
  const std::vector<float> t = {1.0f, 3.0f};
  expect_near(at(t, {0, 0, 0, 4, 2, -2}, 3, Interpolation::Linear, 1.5), {1.0, 0.5, -0.5});
  expect_near(at(t, {0, 0, 0, 4, 2, -2}, 3, Interpolation::Linear, 0.0), {0, 0, 0});
  expect_near(at(t, {0, 0, 0, 4, 2, -2}, 3, Interpolation::Linear, 9.0), {4, 2, -2});
  // Two morph targets, three keys.
  const std::vector<float> t3 = {0.0f, 1.0f, 3.0f};
  expect_near(at(t3, {0, 1, 1, 0, 0.5, 0.5}, 2, Interpolation::Linear, 2.0), {0.75, 0.25});
}

// From no rotation to 90 degrees about z, a third of the way: 30 degrees about z, which a
// componentwise lerp (then normalised) would miss.
TEST(AnimationSampling, LinearRotationIsSlerpOnTheShorterArc) {
  const std::vector<float> t = {0.0f, 3.0f};
  const double h = std::sqrt(0.5);
  const std::vector<double> want = {0, 0, std::sin(kPi / 12), std::cos(kPi / 12)};
  expect_near(at(t, {0, 0, 0, 1, 0, 0, h, h}, 4, Interpolation::Linear, 1.0, true), want);
  // The same end rotation as -q: the shorter arc is the same 30 degrees.
  expect_near(at(t, {0, 0, 0, 1, 0, 0, -h, -h}, 4, Interpolation::Linear, 1.0, true), want);
  // 180 degrees about x to 180 degrees about y (a right angle apart on the sphere), halfway.
  expect_near(at(t, {1, 0, 0, 0, 0, 1, 0, 0}, 4, Interpolation::Linear, 1.5, true), {h, h, 0, 0});
  // Equal keys stay put (no division by the sine of a zero angle).
  expect_near(at(t, {0, 0, h, h, 0, 0, h, h}, 4, Interpolation::Linear, 2.0, true), {0, 0, h, h});
}

// Keys at t = 0 and 2 (interval 2): value 1 with out-tangent 3, value 5 with in-tangent -1.
// At s = 1/2 the Hermite basis is h00 = 1/2, h10 = 1/8, h01 = 1/2, h11 = -1/8:
// 1/2 * 1 + 2 * 1/8 * 3 + 1/2 * 5 + 2 * (-1/8) * (-1) = 4.
TEST(AnimationSampling, CubicSplineFollowsTheHermiteSpline) {
  const std::vector<float> t = {0.0f, 2.0f};
  // Per key: in-tangent, value, out-tangent.
  const std::vector<double> v = {99, 1, 3, -1, 5, 77};
  expect_near(at(t, v, 1, Interpolation::CubicSpline, 1.0), {4.0});
  // At s = 1/4: h00 = 27/32, h10 = 9/64, h01 = 5/32, h11 = -3/64.
  expect_near(at(t, v, 1, Interpolation::CubicSpline, 0.5), {27.0 / 32 + 2 * 9.0 / 64 * 3 + 5.0 / 32 * 5 + 2 * 3.0 / 64});
  expect_near(at(t, v, 1, Interpolation::CubicSpline, 0.0), {1.0});  // the value, not a tangent
  expect_near(at(t, v, 1, Interpolation::CubicSpline, -3.0), {1.0});
  expect_near(at(t, v, 1, Interpolation::CubicSpline, 2.0), {5.0});
  expect_near(at(t, v, 1, Interpolation::CubicSpline, 8.0), {5.0});
}

TEST(AnimationSampling, CubicSplineRotationsComeOutUnitLength) {
  const double h = std::sqrt(0.5);
  const std::vector<double> v = {0, 0, 0, 0, /**/ 0, 0, 0, 1, /**/ 0, 0, 0, 0,  //
                                 0, 0, 0, 0, /**/ 0, 0, h, h, /**/ 0, 0, 0, 0};
  const std::vector<double> q = at({0.0f, 1.0f}, v, 4, Interpolation::CubicSpline, 0.5, true);
  // With zero tangents: (0, 0, h/2, 1/2 + h/2), normalised.
  const double n = std::sqrt(0.25 * h * h + std::pow(0.5 + 0.5 * h, 2));
  expect_near(q, {0, 0, 0.5 * h / n, (0.5 + 0.5 * h) / n});
}

TEST(AnimationSampling, OneKeyframeIsConstant) {
  for (Interpolation mode : {Interpolation::Step, Interpolation::Linear})
    expect_near(at({2.0f}, {7, 8, 9}, 3, mode, -5.0), {7, 8, 9});
  expect_near(at({2.0f}, {0, 4, 0}, 1, Interpolation::CubicSpline, 30.0), {4});
}

}  // namespace
}  // namespace lancer::gltf
