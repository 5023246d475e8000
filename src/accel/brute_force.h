// The oracle: every ray against every triangle, in index order, with the scalar
// watertight test. Slow on purpose and kept forever: every fast path is tested against it.
#pragma once

#include "accel/accelerator.h"

namespace lancer {

class BruteForce final : public Accelerator {
 public:
  // Keeps a reference: `tris` must outlive the accelerator.
  explicit BruteForce(const TriangleSoA& tris) : tris_(tris) {}

  Hit intersect(const Ray& ray) const override;
  bool occluded(const Ray& ray) const override;
  std::size_t memory_bytes() const override { return 0; }
  std::string_view name() const override { return "brute"; }

 private:
  const TriangleSoA& tris_;
};

}  // namespace lancer
