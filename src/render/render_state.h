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
//
// Apart from the samples, the light tracer's (render/light_tracer.h): per pixel the sum of
// what `light_passes` passes of `light_paths` light paths each brought it, and `pending`,
// the next pass's (empty when none is traced ahead). Light pass s belongs to sample s: a
// pixel with more samples than light_passes counts the pending pass too, so each pixel is
// the image of a render of its own sample count, a stop mid-pass included. All empty or 0
// without light tracing.
struct RenderState {
  int width = 0;
  int height = 0;
  int passes = 0;  // full passes over the image
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> count;
  std::vector<glm::dvec3> light;
  std::vector<glm::dvec3> pending;
  int light_passes = 0;
  std::uint64_t light_paths = 0;  // per pass

  bool empty() const { return width == 0; }
  std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  void reset(int w, int h) {
    width = w, height = h, passes = 0;
    sum.assign(pixels(), glm::dvec3(0.0));
    count.assign(pixels(), 0);
    light.clear();
    pending.clear();
    light_passes = 0;
    light_paths = 0;
  }
  // The image: each pixel's mean (black where it has no sample yet), plus its light passes'
  // mean (render/light_tracer.h).
  ImageRGB mean() const {
    ImageRGB image(width, height);
    const bool ahead = !pending.empty();
    const double paths = static_cast<double>(light_paths);
    const double done_scale = light_passes > 0 ? 1.0 / (static_cast<double>(light_passes) * paths) : 0.0;
    const double ahead_scale = 1.0 / ((static_cast<double>(light_passes) + 1.0) * paths);
    for (std::size_t p = 0; p < pixels(); ++p) {
      glm::dvec3 mean = count[p] > 0 ? sum[p] / static_cast<double>(count[p]) : glm::dvec3(0.0);
      if (ahead && count[p] > static_cast<std::uint32_t>(light_passes))
        mean += (light_passes > 0 ? light[p] + pending[p] : pending[p]) * ahead_scale;
      else if (light_passes > 0)
        mean += light[p] * done_scale;
      const glm::vec3 m(mean);
      image.rgb[3 * p] = m.x, image.rgb[3 * p + 1] = m.y, image.rgb[3 * p + 2] = m.z;
    }
    return image;
  }
  // Counts the pending light pass as done.
  void commit_pending() {
    if (pending.empty()) return;
    if (light.empty()) light.assign(pixels(), glm::dvec3(0.0));
    for (std::size_t p = 0; p < pixels(); ++p) light[p] += pending[p];
    pending.clear();
    ++light_passes;
  }
};

}  // namespace lancer
