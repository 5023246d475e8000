// The cosine and sine of an angle given in turns (2 pi u radians), as every sampling routine
// draws a uniform azimuth: cosine-weighted and visible-normal directions, lens points.
//
// Why not std::cos and std::sin of 2 pi u: glibc's sincosf reduces an arbitrary float
// argument and was 2 % of a Cornell box render (two azimuths per bounce). In turns the
// reduction is exact: u * 4 is exact, and so is its distance f to the nearest quarter
// turn q, so only the angle f * pi / 2 in [-pi/4, pi/4] is rounded, once. Taylor
// polynomials to degree 9 (sine) and 10 (cosine) leave truncation errors below 2e-9 there;
// the result is within a few float ulps of the true values (tests/render/turn_test.cpp),
// and exact at every quarter turn.
#pragma once

#include <cmath>
#include <numbers>

#include <glm/vec2.hpp>

namespace lancer {

// (cos(2 pi u), sin(2 pi u)) for |u| <= 2^20 (samplers pass [0, 1)).
inline glm::vec2 turn_cos_sin(float u) {
  const float t = 4.0f * u;
  const float q = std::nearbyint(t);
  const float x = (t - q) * (0.5f * std::numbers::pi_v<float>);  // [-pi/4, pi/4]
  const float x2 = x * x;
  const float s = x * (1.0f + x2 * (-1.0f / 6.0f + x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f)))));
  const float c =
      1.0f + x2 * (-0.5f + x2 * (1.0f / 24.0f + x2 * (-1.0f / 720.0f + x2 * (1.0f / 40320.0f + x2 * (-1.0f / 3628800.0f)))));
  // Rotate by q quarter turns, (c, s) -> (-s, c) for each, as selects: the quarter of a
  // random azimuth is a branch no predictor learns.
  const int k = static_cast<int>(q);
  const bool odd = (k & 1) != 0, half = (k & 2) != 0;
  const float cx = odd ? -s : c, sy = odd ? c : s;
  return {half ? -cx : cx, half ? -sy : sy};
}

}  // namespace lancer
