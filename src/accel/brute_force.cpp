#include "accel/brute_force.h"

#include "accel/watertight.h"

namespace lancer {

Hit BruteForce::intersect(const Ray& ray) const {
  const WatertightRay wr(ray);
  Hit hit;
  hit.t = ray.tfar;
  TriangleHit th;
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    // Strict t < hit.t inside the kernel: on a tie the earlier (lower) index stays.
    if (intersect_watertight(wr, tris_.vertex(i, 0), tris_.vertex(i, 1), tris_.vertex(i, 2), hit.t, th)) {
      hit = {th.t, static_cast<std::uint32_t>(i), th.u, th.v};
    }
  }
  if (!hit.valid()) hit.t = kInfinity;
  return hit;
}

bool BruteForce::occluded(const Ray& ray) const {
  const WatertightRay wr(ray);
  TriangleHit th;
  for (std::size_t i = 0; i < tris_.size(); ++i)
    if (intersect_watertight(wr, tris_.vertex(i, 0), tris_.vertex(i, 1), tris_.vertex(i, 2), ray.tfar, th))
      return true;
  return false;
}

}  // namespace lancer
