// The batch origin solvers (ray_offset_batch.h) against SurfaceOffset, one ray at a time:
// every ISA must give the very same origins, bit for bit, on ordinary rays (the vector
// path) and on those it leaves to the scalar solver (near tangent, near ties between axes,
// degenerate triangles, unusable directions). Runs per ISA (AllIsas/RayOffsetBatch.<Test>/<isa>).
#include "accel/ray_offset_batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "kd_test_support.h"

namespace lancer {
namespace {

using test::KdIsaTest;
using test::TestRng;

class RayOffsetBatch : public KdIsaTest {};

glm::dvec3 unit(TestRng& rng) {
  for (;;) {
    const glm::dvec3 v(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    const double l = glm::length(v);
    if (l > 0.1 && l <= 1.0) return v / l;
  }
}

// The point at barycentrics (u, v), summed in double and rounded once (make_surface_point).
glm::vec3 point_at(const TriangleCorners& t, double u, double v) {
  return glm::vec3(glm::dvec3(t[0]) * (1.0 - u - v) + glm::dvec3(t[1]) * u + glm::dvec3(t[2]) * v);
}

// A unit direction at angle asin(cos_min .. 1) above (or below) the plane of normal n.
glm::vec3 direction_from(TestRng& rng, const glm::dvec3& n, double cos_min, bool below) {
  glm::dvec3 w = unit(rng);
  w = glm::normalize(w - glm::dot(w, n) * n);
  const double c = cos_min + (1.0 - cos_min) * rng.uniform();
  return glm::vec3((below ? -c : c) * n + std::sqrt(1.0 - c * c) * w);
}

struct Case {
  std::vector<SurfaceOffset> leaves;
  std::vector<OriginRequest> requests;
};

void add(Case& c, const SurfaceOffset& leave, const glm::vec3& target, bool towards) {
  c.leaves.push_back(leave);
  c.requests.push_back({nullptr, target, towards});
}

// Points on random triangles of every size and place, rays of every kind from them.
Case mixed_case(TestRng& rng, int count, bool hostile) {
  Case c;
  c.leaves.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double size = std::pow(10.0, 6.0 * rng.uniform() - 3.0);
    const glm::dvec3 centre = std::pow(10.0, 4.0 * rng.uniform() - 1.0) * unit(rng);
    TriangleCorners t;
    const int shape = hostile ? static_cast<int>(rng.below(4)) : 0;
    for (glm::vec3& v : t) v = glm::vec3(centre + size * unit(rng));
    if (shape == 1) {  // axis-aligned: a face of a box
      for (glm::vec3& v : t) v.z = t[0].z;
    } else if (shape == 2) {  // a sliver
      t[2] = glm::vec3(glm::dvec3(t[0]) + (glm::dvec3(t[1]) - glm::dvec3(t[0])) * 0.5 + 1e-4 * size * unit(rng));
    } else if (shape == 3 && rng.uniform() < 0.2) {  // no area at all
      t[2] = t[1];
    }
    const glm::vec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
    glm::vec3 n = glm::cross(e1, e2);
    n = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, 1);
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    if (hostile && rng.uniform() < 0.2) v = 0.0;  // on an edge
    const SurfaceOffset leave(point_at(t, u, v), rng.uniform() < 0.5 ? n : -n, t);
    const glm::dvec3 nd(n);
    glm::vec3 dir;
    const int kind = hostile ? static_cast<int>(rng.below(6)) : static_cast<int>(rng.below(2));
    switch (kind) {
      case 0: dir = direction_from(rng, nd, 1e-3, false); break;
      case 1: dir = direction_from(rng, nd, 1e-3, true); break;
      case 2: dir = direction_from(rng, nd, 0.0, rng.uniform() < 0.5) * 1e-3f; break;  // within 1e-3 .. tangent
      case 3: {  // two axes tied (the kernel may pick either)
        const float a = rng.uniform() < 0.5 ? 1.0f : -1.0f;
        dir = glm::vec3(a, rng.uniform() < 0.5 ? 1.0f : -1.0f, float(rng.uniform()) * 0.9f);
        break;
      }
      case 4: dir = glm::vec3(0.0f, 0.0f, rng.uniform() < 0.5 ? 1.0f : -1.0f); break;  // along an axis
      default: dir = rng.uniform() < 0.5 ? glm::vec3(0.0f) : glm::vec3(std::nanf(""), 1.0f, 0.0f); break;
    }
    if (rng.uniform() < 0.5) {
      const glm::vec3 p = point_at(t, u, v);
      add(c, leave, p + dir * float(size * std::pow(10.0, 3.0 * rng.uniform())), true);  // a segment's end
    } else {
      add(c, leave, dir, false);
    }
  }
  for (std::size_t i = 0; i < c.requests.size(); ++i) c.requests[i].leave = &c.leaves[i];
  return c;
}

// Returns the number of requests the batch left to the scalar solver.
int expect_same_origins(const Case& c, Isa isa) {
  const int n = static_cast<int>(c.requests.size());
  std::vector<glm::vec3> batch(c.requests.size());
  const int scalar_lanes = solve_origins(c.requests.data(), batch.data(), n, isa);
  int mismatches = 0;
  for (int i = 0; i < n; ++i) {
    const OriginRequest& r = c.requests[static_cast<std::size_t>(i)];
    const glm::vec3 want = r.towards ? r.leave->origin_towards(r.target) : r.leave->origin(r.target);
    const glm::vec3& got = batch[static_cast<std::size_t>(i)];
    if (std::memcmp(&want, &got, sizeof want) != 0 && ++mismatches <= 5)
      ADD_FAILURE() << "request " << i << (r.towards ? " (towards)" : " (direction)") << ": batch (" << got.x << ", "
                    << got.y << ", " << got.z << "), scalar (" << want.x << ", " << want.y << ", " << want.z << ")";
  }
  EXPECT_EQ(mismatches, 0) << "of " << n << " requests";
  return scalar_lanes;
}

TEST_P(RayOffsetBatch, OrdinaryRaysTakeTheVectorPathAndGiveTheScalarOrigins) {
  TestRng rng(31 + isa_seed());
  const Case c = mixed_case(rng, 3000, false);
  const int scalar_lanes = expect_same_origins(c, isa());
  if (isa() == Isa::Scalar) {
    EXPECT_EQ(scalar_lanes, 3000);
  } else {
    EXPECT_LT(scalar_lanes, 300) << "most ordinary rays should take the vector path";
  }
}

TEST_P(RayOffsetBatch, HostileRaysGiveTheScalarOrigins) {
  TestRng rng(32 + isa_seed());
  const Case c = mixed_case(rng, 6000, true);
  const int scalar_lanes = expect_same_origins(c, isa());
  EXPECT_GT(scalar_lanes, 0) << "some rays should need the scalar solver";
  if (isa() != Isa::Scalar) {
    EXPECT_LT(scalar_lanes, 6000) << "and others the vector path";
  }
}

// Counts that are not a multiple of the vector width, or beyond one call's lanes.
TEST_P(RayOffsetBatch, AnyCount) {
  TestRng rng(33 + isa_seed());
  for (const int count : {0, 1, 3, 7, 63, 64, 65, 200}) {
    const Case c = mixed_case(rng, count, false);
    expect_same_origins(c, isa());
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, RayOffsetBatch, ::testing::ValuesIn(test::kd_test_isas()), test::kd_isa_param_name);

}  // namespace
}  // namespace lancer
