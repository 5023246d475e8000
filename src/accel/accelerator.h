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

  // Closest hit with tnear <= t < tfar; ties in t go to the lowest instance, then the lowest
  // triangle index.
  virtual Hit intersect(const Ray& ray) const = 0;
  // True when any triangle is hit with tnear <= t < tfar.
  virtual bool occluded(const Ray& ray) const = 0;
  // Closest hits of rays[0..count), each exactly what intersect() gives. Accelerators with
  // packet traversal override it (coherent rays, e.g. an 8x8 pixel block, share work);
  // this default traces the rays one by one. count must be >= 0.
  virtual void intersect_packet(const Ray* rays, Hit* hits, int count) const {
    for (int i = 0; i < count; ++i) hits[i] = intersect(rays[i]);
  }
  // occluded[i] = occluded(rays[i]) for rays[0..count): the same contract for occlusion
  // (shadow rays towards one light from neighbouring points).
  virtual void occluded_packet(const Ray* rays, bool* occluded, int count) const {
    for (int i = 0; i < count; ++i) occluded[i] = this->occluded(rays[i]);
  }

  // Bytes the accelerator holds beyond the input triangles.
  virtual std::size_t memory_bytes() const = 0;
  virtual std::string_view name() const = 0;
};

}  // namespace lancer
