// Memory of the two-level accelerator: a mesh drawn many times is stored once, and each
// instance costs a bounded number of bytes (its Instance record, about 100 bytes, plus its
// top-level references and share of the nodes).
#include <cstdint>

#include <gtest/gtest.h>

#include "accel/kd_tree.h"
#include "accel/two_level.h"
#include "two_level_test_support.h"

namespace lancer::test {
namespace {

// n instances of one mesh on a grid of cells 3 units apart (the mesh spans 2), each
// rotated and scaled at random.
InstancedScene grid_of(const TriangleSoA& mesh, std::size_t n) {
  InstancedScene s;
  s.tris = mesh;
  s.geometry.meshes = {{0, static_cast<std::uint32_t>(mesh.size())}};
  TestRng rng(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 at(3.0 * double(i % 25), 3.0 * double(i / 25 % 25), 3.0 * double(i / 625));
    const glm::dvec3 scale(rng.uniform(0.5f, 1.0f), rng.uniform(0.5f, 1.0f), rng.uniform(0.5f, 1.0f));
    s.geometry.instances.push_back(make_instance(0, random_linear(rng, scale), at));
  }
  return s;
}

// At most 256 bytes per instance on average between 10 and 10,000 instances of a
// 5,000-triangle mesh; the mesh's tree (hundreds of kilobytes) is held once.
TEST(TwoLevelMemory, InstancesCostBoundedBytesAndTheMeshIsStoredOnce) {
  const TriangleSoA mesh = random_soup(5000, 42, {{-1, -1, -1}, {1, 1, 1}}, 0.2f);
  const KdTree alone(mesh);
  const InstancedScene few = grid_of(mesh, 10), many = grid_of(mesh, 10000);
  const TwoLevelAccelerator a(few.tris, few.geometry, "kdtree"), b(many.tris, many.geometry, "kdtree");
  EXPECT_EQ(b.bottom_count(), 1u);
  EXPECT_GE(a.memory_bytes(), alone.memory_bytes()) << "the mesh's tree counts";
  EXPECT_LT(a.memory_bytes(), 2 * alone.memory_bytes()) << "and counts once";
  const double per_instance = double(b.memory_bytes() - a.memory_bytes()) / double(10000 - 10);
  EXPECT_LE(per_instance, 256.0) << b.memory_bytes() << " bytes for 10,000 instances, " << a.memory_bytes()
                                 << " for 10; top-level nodes " << b.top_level().nodes().size() << ", references "
                                 << b.top_level().items().size();
}

}  // namespace
}  // namespace lancer::test
