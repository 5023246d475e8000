// The mean of an image channel over its pixels and the standard error of that mean, for
// tests that compare a render with a closed form within the noise they measure; and the
// largest difference of block means, for tests that compare two renders that follow the
// same paths.
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

// The largest relative difference of the two images' block x block pixel means (over the
// three channels), relative to the reference block or, for dark blocks, to a tenth of the
// reference image's mean. The images have the same size, a multiple of `block`.
inline double largest_block_difference(const ImageRGB& image, const ImageRGB& reference, int block) {
  double mean = 0.0;
  for (float v : reference.rgb) mean += v;
  mean /= static_cast<double>(reference.rgb.size());
  const double floor = 0.1 * mean * 3.0 * block * block;
  double worst = 0.0;
  for (int by = 0; by < reference.height; by += block)
    for (int bx = 0; bx < reference.width; bx += block) {
      double a = 0.0, b = 0.0;
      for (int y = by; y < by + block; ++y)
        for (int x = bx; x < bx + block; ++x)
          for (int c = 0; c < 3; ++c) {
            const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(reference.width) +
                                       static_cast<std::size_t>(x)) +
                                  static_cast<std::size_t>(c);
            a += image.rgb[i];
            b += reference.rgb[i];
          }
      worst = std::max(worst, std::fabs(a - b) / std::max(b, floor));
    }
  return worst;
}

}  // namespace lancer::test
