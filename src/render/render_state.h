// What a progressive render has accumulated so far, exactly: enough to continue it later
// (lancer render --resume) and end with the image an uninterrupted render gives, bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "render/image.h"

namespace lancer {

// Per pixel, row-major: the sum of its samples in the order they were taken (pass 0, 1,
// ...) and how many there are. Every pixel has `passes` or `passes + 1` samples: a render
// stopped in the middle of pass `passes` leaves some pixels one sample ahead. Empty
// (width 0): nothing rendered yet.
struct RenderState {
  int width = 0;
  int height = 0;
  int passes = 0;  // full passes over the image
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> count;

  bool empty() const { return width == 0; }
  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  void reset(int w, int h) {
    width = w, height = h, passes = 0;
    sum.assign(pixels(), glm::dvec3(0.0));
    count.assign(pixels(), 0);
  }
  // The image: each pixel's mean (black where it has no sample yet).
  ImageRGB mean() const {
    ImageRGB image(width, height);
    for (std::size_t p = 0; p < pixels(); ++p) {
      const glm::vec3 m = count[p] > 0 ? glm::vec3(sum[p] / static_cast<double>(count[p])) : glm::vec3(0.0f);
      image.rgb[3 * p] = m.x, image.rgb[3 * p + 1] = m.y, image.rgb[3 * p + 2] = m.z;
    }
    return image;
  }
};

}  // namespace lancer
