// The interface every ray/scene intersector offers to the renderer.
// One virtual call per ray (or per packet): never inside a traversal loop.
#pragma once

#include <cstddef>
#include <memory>
#include <string_view>

#include "accel/ray.h"
#include "accel/triangle_soa.h"

namespace lancer {

class Accelerator {
 public:
  virtual ~Accelerator() = default;

  // Closest hit with tnear <= t < tfar; ties in t go to the lowest triangle index.
  virtual Hit intersect(const Ray& ray) const = 0;
  // True when any triangle is hit with tnear <= t < tfar.
  virtual bool occluded(const Ray& ray) const = 0;

  // Bytes the accelerator holds beyond the input triangles.
  virtual std::size_t memory_bytes() const = 0;
  virtual std::string_view name() const = 0;
};

}  // namespace lancer
