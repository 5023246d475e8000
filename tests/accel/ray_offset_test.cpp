#include "accel/ray_offset.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lancer {
namespace {

TEST(RayOffset, MovesAlongTheNormalSide) {
  for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(1e-3f, -2e-3f, 0.0f), glm::vec3(12.5f, -300.0f, 4e4f)}) {
    for (const glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0, -1, 0), glm::vec3(0.6f, 0.0f, -0.8f)}) {
      const glm::vec3 q = offset_ray_origin(p, n);
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(q[i] > p[i], n[i] > 0.0f) << i;
        EXPECT_EQ(q[i] < p[i], n[i] < 0.0f) << i;
      }
    }
  }
}

// The offset is a fixed number of ulps: relative to the coordinate, it stays tiny.
TEST(RayOffset, ScalesWithMagnitude) {
  const glm::vec3 n(0, 0, 1);
  for (float z : {1.0f, 1e3f, 1e6f, -1e6f}) {
    const glm::vec3 q = offset_ray_origin(glm::vec3(0, 0, z), n);
    const float moved = std::fabs(q.z - z);
    EXPECT_GT(moved, 0.0f);
    EXPECT_LT(moved / std::fabs(z), 1e-4f) << z;
  }
}

}  // namespace
}  // namespace lancer
