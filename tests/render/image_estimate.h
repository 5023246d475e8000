// The mean of an image channel over its pixels and the standard error of that mean, for
// tests that compare a render with a closed form within the noise they measure.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "render/image.h"

namespace lancer::test {

struct Estimate {
  double mean = 0.0, stderr_ = 0.0;
};

// Mean over the pixels of channel c, and its standard error (pixels are independent; the
// sample variance with n - 1).
inline Estimate estimate(const ImageRGB& image, int c) {
  const std::size_t n = image.rgb.size() / 3;
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = image.rgb[3 * i + static_cast<std::size_t>(c)];
    sum += v;
    sum2 += v * v;
  }
  const double count = static_cast<double>(n);
  const double mean = sum / count;
  const double var = std::max(0.0, sum2 / count - mean * mean) * count / (count - 1.0);
  return {mean, std::sqrt(var / count)};
}

}  // namespace lancer::test
