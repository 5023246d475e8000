// What stays watertight through instances: a closed mesh drawn through a turned, scaled,
// mirrored and far-moved instance has no cracks, since its triangles are all tested in
// the mesh's own space on one transformed ray (Woop et al. 2013 holds there as in a
// one-level scene). Rays from inside aimed at its corners and edges always hit it, packets
// and single rays, every ISA. (Where two instances meet, their edges go through different
// transforms: no such promise, as between two separately modelled objects.)
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "accel/accel_factory.h"
#include "scene/procedural.h"
#include "simd/isa.h"
#include "simd/splitmix64.h"

namespace lancer {
namespace {

Instance placed(const glm::dmat3& linear, const glm::dvec3& offset) {
  const glm::dmat3 inverse = glm::inverse(linear);
  Instance inst;
  inst.to_world = Affine{glm::mat3(linear), glm::vec3(offset)};
  inst.to_object = Affine{glm::mat3(inverse), glm::vec3(-(inverse * offset))};
  return inst;
}

TEST(TwoLevelWatertight, ClosedMeshThroughAnyInstanceHasNoCracks) {
  Scene sphere;
  append_icosphere(sphere, glm::vec3(0.0f), 1.0f, 3, 0);
  InstancedGeometry g;
  g.meshes.push_back({0, std::uint32_t(sphere.triangle_count())});
  const double c = std::cos(0.8), s = std::sin(0.8);
  const glm::dmat3 turn(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
  const glm::dmat3 squash(2.5, 0.0, 0.0, 0.0, 0.4, 0.0, 0.0, 0.0, -1.3);  // mirrors
  g.instances.push_back(placed(turn * squash, {3e3, -2e3, 5e2}));
  g.instances.push_back(placed(glm::dmat3(1e-2), {0.5, 0.25, -1.0}));
  SplitMix64 rng(11);
  for (Isa isa : supported_isas()) {
    const std::unique_ptr<Accelerator> accel = make_accelerator("kdtree", sphere.triangles, g, {}, isa);
    int misses = 0, rays = 0;
    for (const Instance& inst : g.instances) {
      std::vector<Ray> batch;
      for (std::uint32_t t = 0; t < sphere.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
          const glm::vec3 a = sphere.triangles.vertex(t, k), b = sphere.triangles.vertex(t, (k + 1) % 3);
          for (const glm::vec3& target : {a, a + 0.5f * (b - a), a + float(rng.uniform()) * (b - a)}) {
            // From near the centre (in the mesh's space), moved to world space.
            const glm::vec3 inside(0.3f * (float(rng.uniform()) - 0.5f), 0.3f * (float(rng.uniform()) - 0.5f),
                                   0.3f * (float(rng.uniform()) - 0.5f));
            Ray r;
            r.org = inst.to_world.point(inside);
            r.dir = inst.to_world.vector(target - inside);
            batch.push_back(r);
          }
        }
      std::vector<Hit> hits(batch.size());
      accel->intersect_packet(batch.data(), hits.data(), int(batch.size()));
      for (std::size_t i = 0; i < batch.size(); ++i) {
        misses += !hits[i].valid() || !accel->intersect(batch[i]).valid() || !accel->occluded(batch[i]);
        ++rays;
      }
    }
    EXPECT_EQ(misses, 0) << "of " << rays << " rays from inside, isa " << isa_name(isa);
  }
}

}  // namespace
}  // namespace lancer
