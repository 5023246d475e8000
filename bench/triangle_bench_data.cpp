// The triangle-test benchmarks' data, tables and check (see triangle_bench_data.h).
#include "triangle_bench_data.h"

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "accel/watertight.h"
#include "simd/splitmix64.h"

namespace lancer::bench {
namespace {

glm::vec3 uniform_in_box(SplitMix64& rng, float lo, float hi) {
  const float s = hi - lo;
  const float a = rng.uniform(), b = rng.uniform(), c = rng.uniform();
  return {lo + s * a, lo + s * b, lo + s * c};
}

TriangleBenchData make_data() {
  TriangleBenchData d;
  SplitMix64 rng(5);
  // Triangles about one unit across around the origin, centres in a unit cube ...
  for (int i = 0; i < kBenchTriangles; ++i) {
    const glm::vec3 c = uniform_in_box(rng, -0.5f, 0.5f);
    const glm::vec3 a = c + uniform_in_box(rng, -0.5f, 0.5f);
    const glm::vec3 b = c + uniform_in_box(rng, -0.5f, 0.5f);
    d.triangles.push_back(a, b, c + uniform_in_box(rng, -0.5f, 0.5f));
  }
  // ... and rays from four units away towards points in that cube, in all directions.
  for (int r = 0; r < kBenchRays; ++r) {
    glm::vec3 away;
    do {
      away = uniform_in_box(rng, -1.0f, 1.0f);
    } while (glm::dot(away, away) < 0.01f || glm::dot(away, away) > 1.0f);
    Ray ray;
    ray.org = 4.0f * away / std::sqrt(glm::dot(away, away));
    ray.dir = uniform_in_box(rng, -0.5f, 0.5f) - ray.org;
    d.rays.push_back(ray);
  }
  d.hit.resize(std::size_t(kBenchRays) * kBenchTriangles);
  d.t.resize(d.hit.size());
  for (int r = 0; r < kBenchRays; ++r) {
    const WatertightRay wr(d.rays[std::size_t(r)]);
    for (int i = 0; i < kBenchTriangles; ++i) {
      const std::size_t at = std::size_t(r) * kBenchTriangles + std::size_t(i);
      TriangleHit h{};
      const auto& tri = d.triangles;
      d.hit[at] = intersect_watertight(wr, tri.vertex(i, 0), tri.vertex(i, 1), tri.vertex(i, 2), kInfinity, h);
      d.t[at] = d.hit[at] ? h.t : 0.0f;
      d.hits += d.hit[at];
    }
  }
  return d;
}

}  // namespace

const TriangleBenchData& triangle_bench_data() {
  static const TriangleBenchData data = make_data();
  return data;
}

AlignedVector<float> triangle_blocks(const TriangleSoA& triangles, int block_width) {
  const std::size_t w = std::size_t(block_width), n = triangles.size();
  AlignedVector<float> blocks((n + w - 1) / w * 9 * w, std::nanf(""));  // padding never hits
  for (std::size_t i = 0; i < n; ++i) {
    float* lane = blocks.data() + i / w * 9 * w + i % w;
    for (std::size_t k = 0; k < 3; ++k) {
      lane[k * w] = triangles.x[k][i];
      lane[(3 + k) * w] = triangles.y[k][i];
      lane[(6 + k) * w] = triangles.z[k][i];
    }
  }
  return blocks;
}

std::optional<TriangleKernels> triangle_kernels_for(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return scalar::triangle_bench_kernels();
#if defined(__x86_64__) || defined(_M_X64)
    case Isa::Sse4: return sse4::triangle_bench_kernels();
    case Isa::Avx2: return avx2::triangle_bench_kernels();
    case Isa::Avx512: return avx512::triangle_bench_kernels();
#endif
    default: return std::nullopt;
  }
}

std::string check_triangle_kernels(const TriangleKernels& kernels, const TriangleBenchData& data, const float* blocks,
                                   const void* leaf_rays, std::int64_t& edge_zero_lanes) {
  std::vector<LaneStatus> status(data.hit.size());
  std::vector<float> t(data.hit.size());
  kernels.record(leaf_rays, kBenchRays, blocks, kBenchTriangles, kInfinity, status.data(), t.data());
  edge_zero_lanes = 0;
  std::int64_t hits = 0;
  char text[240];
  for (std::size_t at = 0; at < status.size(); ++at) {
    if (status[at] == LaneStatus::EdgeZero) {
      ++edge_zero_lanes;
      continue;
    }
    const bool hit = status[at] == LaneStatus::Hit;
    hits += hit;
    const int ray = int(at / kBenchTriangles), triangle = int(at % kBenchTriangles);
    if (hit != (data.hit[at] != 0)) {
      std::snprintf(text, sizeof text, "ray %d, triangle %d: the w%d leaf test says %s, the scalar watertight kernel %s",
                    ray, triangle, kernels.width, hit ? "hit" : "miss", data.hit[at] ? "hit" : "miss");
      return text;
    }
    if (hit && t[at] != data.t[at]) {
      std::snprintf(text, sizeof text, "ray %d, triangle %d: the w%d leaf test gives t = %.9g, the scalar kernel %.9g",
                    ray, triangle, kernels.width, double(t[at]), double(data.t[at]));
      return text;
    }
  }
  const std::int64_t counted = kernels.count_hits(leaf_rays, kBenchRays, blocks, kBenchTriangles, kInfinity);
  if (counted != hits) {
    std::snprintf(text, sizeof text, "the timed loop counts %lld hits, the recorded tests %lld", (long long)counted,
                  (long long)hits);
    return text;
  }
  return {};
}

}  // namespace lancer::bench
