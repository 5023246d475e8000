// A linear RGB float image and the files it is written to and read from.
#pragma once

#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace lancer {

// Linear RGB, 3 floats per pixel, rows top to bottom.
struct ImageRGB {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;

  ImageRGB() = default;
  ImageRGB(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}

  glm::vec3 at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, const glm::vec3& c) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    rgb[i] = c.x;
    rgb[i + 1] = c.y;
    rgb[i + 2] = c.z;
  }
};

}  // namespace lancer
