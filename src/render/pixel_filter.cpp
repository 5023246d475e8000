#include "render/pixel_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lancer {

double erf_inverse(double y) {
  if (!(y > -1.0 && y < 1.0)) return std::isnan(y) ? y : std::copysign(HUGE_VAL, y);
  if (y == 0.0) return 0.0;
  // First guess: Winitzki's approximation (about 2e-3 relative error), then Newton steps,
  // each of which squares the error; erf is monotone, so the iteration cannot wander.
  constexpr double kA = 0.147;
  const double l = std::log((1.0 - y) * (1.0 + y));
  const double t = 2.0 / (std::numbers::pi * kA) + 0.5 * l;
  double z = std::copysign(std::sqrt(std::sqrt(t * t - l / kA) - t), y);
  const double two_over_sqrt_pi = 2.0 / std::sqrt(std::numbers::pi);
  for (int i = 0; i < 8; ++i) {
    const double step = (std::erf(z) - y) / (two_over_sqrt_pi * std::exp(-z * z));
    z -= step;
    if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(z))) break;
  }
  return z;
}

PixelFilter::PixelFilter(PixelFilterType type, float sigma, float radius)
    : type_(type), sigma_(sigma), radius_(radius) {
  if (type == PixelFilterType::Gaussian)
    erf_bound_ = std::erf(static_cast<double>(radius) / (static_cast<double>(sigma) * std::numbers::sqrt2));
}

PixelFilter PixelFilter::box() { return PixelFilter(PixelFilterType::Box, 0.0f, 0.5f); }

PixelFilter PixelFilter::gaussian(float sigma, float radius) {
  if (!(std::isfinite(sigma) && sigma > 0.0f) || !(std::isfinite(radius) && radius > 0.0f))
    throw std::invalid_argument("Gaussian pixel filter: sigma and radius must be finite and positive");
  return PixelFilter(PixelFilterType::Gaussian, sigma, radius);
}

float PixelFilter::sample_axis(float u) const {
  // u - 0.5 is exact for u in [0.25, 1) and rounds at most to -0.5 below: [-0.5, 0.5).
  if (type_ == PixelFilterType::Box) return u - 0.5f;
  const double y = (2.0 * static_cast<double>(u) - 1.0) * erf_bound_;
  const double x = static_cast<double>(sigma_) * std::numbers::sqrt2 * erf_inverse(y);
  return std::clamp(static_cast<float>(x), -radius_, radius_);
}

glm::vec2 PixelFilter::sample_offset(glm::vec2 u) const { return {sample_axis(u.x), sample_axis(u.y)}; }

}  // namespace lancer
