// Pixel reconstruction filters, applied by filter importance sampling (Ernst, Stamminger
// & Greiner, "Filter Importance Sampling", IEEE RT 2006; pbrt-v4's FilterSampler): the
// offset of each camera sample from the pixel centre is drawn from the filter itself, so
// every sample has weight exactly 1 and the pixel value is the plain mean of its samples.
// (Filters with negative lobes would need signed weights; none is offered.)
//
//  - Box: the pixel's own square, offsets uniform in [-0.5, 0.5)^2 (the classic jitter).
//  - Gaussian: separable, exp(-x^2 / (2 sigma^2)) exp(-y^2 / (2 sigma^2)) truncated to the
//    square [-radius, radius]^2 and renormalised (not shifted down to reach 0 at the
//    radius). Each axis is a truncated normal, sampled exactly by inverting its CDF:
//      x = sigma sqrt(2) erfinv((2u - 1) erf(radius / (sigma sqrt(2)))).
//    Defaults sigma 0.5 px, radius 1.5 px (three sigma).
// Offsets are in pixels; +x right, +y down, like the camera's pixel coordinates.
#pragma once

#include <glm/vec2.hpp>

namespace lancer {

enum class PixelFilterType { Box, Gaussian };

class PixelFilter {
 public:
  static PixelFilter box();
  // Throws std::invalid_argument unless sigma and radius are finite and > 0.
  static PixelFilter gaussian(float sigma = 0.5f, float radius = 1.5f);

  // u in [0, 1)^2 -> offset from the pixel centre, inside [-radius, radius]^2 (box:
  // [-0.5, 0.5)^2). Monotone in each coordinate, so stratified u stay stratified.
  glm::vec2 sample_offset(glm::vec2 u) const;

  PixelFilterType type() const { return type_; }
  float radius() const { return radius_; }
  float sigma() const { return sigma_; }  // 0 for the box

 private:
  PixelFilter(PixelFilterType type, float sigma, float radius);
  float sample_axis(float u) const;

  PixelFilterType type_ = PixelFilterType::Box;
  float sigma_ = 0.0f;
  float radius_ = 0.5f;
  double erf_bound_ = 0.0;  // erf(radius / (sigma sqrt 2)), Gaussian only
};

// Inverse of the error function on (-1, 1), to double precision (Newton's method on
// std::erf from a closed-form first guess). Exposed for tests.
double erf_inverse(double y);

}  // namespace lancer
