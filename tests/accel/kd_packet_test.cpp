// Packet traversal (KdTree::intersect_packet, kd_packet-inl.h) against the oracle and the
// single-ray kernel: every ray of every packet must get the same triangle and bit-identical
// t, u, v; the same rays as occlusion packets (KdTree::occluded_packet) the same answers as
// the any-hit kernel and the oracle. Runs per ISA (AllIsas/KdPacket.<Test>/<isa>).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "accel/brute_force.h"
#include "accel/kd_traverse_setup.h"
#include "accel/kd_tree.h"
#include "accel/ray_offset.h"
#include "kd_test_support.h"
#include "scene/load_scene.h"
#include "scene/procedural.h"
#include "test_paths.h"

namespace lancer::test {
namespace {

bool mixed_signs(const std::vector<Ray>& rays) {
  for (int a = 0; a < 3; ++a) {
    bool neg = false, pos = false;
    for (const Ray& r : rays) (r.dir[a] < 0.0f ? neg : pos) = true;
    if (neg && pos) return true;
  }
  return false;
}

// What a set of packets covered, so each test can check it exercised what it claims.
struct Coverage {
  std::size_t rays = 0, hits = 0, partial_packets = 0, mixed_sign_packets = 0;
};

class KdPacket : public KdIsaTest {
 protected:
  // Checks one packet; with `check_oracle` false only against the single-ray kernel
  // (itself tested against the oracle elsewhere), for large meshes.
  void check_packet(const KdTree& kd, const BruteForce& oracle, const std::vector<Ray>& rays, Coverage& cov,
                    bool check_oracle = true) {
    std::vector<Hit> hits(rays.size());
    kd.intersect_packet(rays.data(), hits.data(), static_cast<int>(rays.size()));
    std::size_t hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Hit single = kd.intersect(rays[i]);
      ASSERT_TRUE(same_hit(hits[i], single))
          << "packet lane " << i << " of " << rays.size() << ", " << describe(rays[i]) << ": packet prim "
          << hits[i].prim << " t " << hits[i].t << ", single-ray prim " << single.prim << " t " << single.t;
      if (check_oracle) {
        const Hit expected = oracle.intersect(rays[i]);
        ASSERT_TRUE(same_hit(hits[i], expected))
            << "packet lane " << i << ", " << describe(rays[i]) << ": packet prim " << hits[i].prim << " t "
            << hits[i].t << ", oracle prim " << expected.prim << " t " << expected.t;
      }
      hit_count += hits[i].valid() ? 1 : 0;
    }
    check_occlusion_packet(kd, oracle, rays, check_oracle);
    cov.rays += rays.size();
    cov.hits += hit_count;
    cov.partial_packets += (hit_count > 0 && hit_count < rays.size()) ? 1 : 0;
    cov.mixed_sign_packets += mixed_signs(rays) ? 1 : 0;
  }

  // The same rays as one occlusion packet (lanes leave at their first hit): the answers
  // of the single-ray any-hit kernel and the oracle.
  void check_occlusion_packet(const KdTree& kd, const BruteForce& oracle, const std::vector<Ray>& rays,
                              bool check_oracle = true) {
    const std::unique_ptr<bool[]> blocked(new bool[rays.size() + 1]);
    kd.occluded_packet(rays.data(), blocked.get(), static_cast<int>(rays.size()));
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(blocked[i], kd.occluded(rays[i])) << "occlusion packet lane " << i << " of " << rays.size() << ", "
                                                  << describe(rays[i]) << " against the single-ray kernel";
      if (check_oracle) {
        ASSERT_EQ(blocked[i], oracle.occluded(rays[i]))
            << "occlusion packet lane " << i << " of " << rays.size() << ", " << describe(rays[i]) << " against the oracle";
      }
    }
  }

  void check_tiles(const KdTree& kd, const BruteForce& oracle, const std::vector<std::vector<Ray>>& tiles,
                   Coverage& cov, bool check_oracle = true) {
    for (const auto& t : tiles) {
      check_packet(kd, oracle, t, cov, check_oracle);
      if (HasFatalFailure()) return;
    }
  }

  // Camera views of `tris`: from outside at two distances and from inside the box, with a
  // wide view straight down an axis (tiles at the image centre have mixed signs).
  void check_camera_views(const TriangleSoA& tris, int size, bool check_oracle = true) {
    const KdTree kd(tris, {}, isa());
    const BruteForce oracle(tris);
    const Bounds3 b = tris.bounds();
    const glm::vec3 c = b.center(), e = b.extent();
    const float reach = std::fmax(e.x, std::fmax(e.y, e.z));
    Coverage cov;
    const Pinhole views[] = {
        Pinhole::looking_at(c + glm::vec3(0.3f, 0.4f, 1.6f) * reach, c, {0, 1, 0}, 40.0f, size),
        Pinhole::looking_at(c + glm::vec3(-0.9f, 0.2f, -0.7f) * reach, c, {0, 1, 0}, 55.0f, size),
        Pinhole::looking_at(c + glm::vec3(0.0f, 0.0f, 0.35f) * e, c - glm::vec3(0, 0, reach), {0, 1, 0}, 100.0f, size),
    };
    for (const Pinhole& v : views) {
      check_tiles(kd, oracle, camera_tiles(v, size, size), cov, check_oracle);
      if (HasFatalFailure()) return;
    }
    EXPECT_GT(cov.hits, cov.rays / 10) << "the views should mostly see the scene";
    EXPECT_GT(cov.partial_packets, 0u) << "some packets should hit with only some rays";
    EXPECT_GT(cov.mixed_sign_packets, 0u) << "the wide view should give packets with mixed direction signs";
  }
};

TriangleSoA spheres_and_boxes() {
  Scene s;
  append_uv_sphere(s, {0.0f, 1.0f, 0.0f}, 1.0f, 24, 12, 0);
  append_icosphere(s, {2.2f, 0.6f, -0.5f}, 0.6f, 2, 0);
  append_box(s, {{-3.0f, -0.2f, -3.0f}, {3.0f, 0.0f, 3.0f}}, 0);
  append_box(s, {{-2.5f, 0.0f, 0.8f}, {-1.3f, 1.7f, 1.9f}}, 0);
  append_box(s, {{0.9f, 0.0f, 1.2f}, {1.4f, 0.5f, 1.7f}}, 0);
  return s.triangles;
}

TEST_P(KdPacket, CameraTilesSpheresAndBoxes) { check_camera_views(spheres_and_boxes(), 64); }

TEST_P(KdPacket, CameraTilesCornellSpheres) {
  const Scene scene = load_scene(scenes_dir() / "cornell-box-spheres.gltf");
  check_camera_views(scene.triangles, 48);
}

TEST_P(KdPacket, CameraTilesBunny) {
  const std::filesystem::path path = models_dir() / "stanford-bunny.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent: the shared meshes are not installed";
  const Scene scene = load_scene(path);
  check_camera_views(scene.triangles, 64, /*check_oracle=*/false);
  if (HasFatalFailure()) return;
  // The oracle on a smaller image (it tests every triangle).
  check_camera_views(scene.triangles, 16);
}

// Rays from one point through vertices and edge midpoints of nearby triangles: hits on
// shared edges and vertices, where the zero-edge lanes take the scalar kernel.
TEST_P(KdPacket, GrazingEdgesAndVertices) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  TestRng rng(isa_seed() + 7);
  Coverage cov;
  for (int p = 0; p < 24; ++p) {
    const glm::vec3 eye = rng.in_box(grown(tris.bounds(), 0.3f));
    const std::uint32_t first = rng.below(static_cast<std::uint32_t>(tris.size() - 64));
    std::vector<Ray> rays;
    for (std::uint32_t i = 0; i < 64; ++i) {
      const std::uint32_t tri = first + i / 2;
      const glm::vec3 target =
          (i % 2 == 0) ? tris.vertex(tri, int(i / 2 % 3)) : 0.5f * (tris.vertex(tri, 0) + tris.vertex(tri, 1));
      Ray r;
      r.org = eye;
      r.dir = target - eye;
      rays.push_back(r);
    }
    check_packet(kd, oracle, rays, cov);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(cov.hits, cov.rays / 4);
}

// Every lane the same ray, and partial packets of 1..63 rays.
TEST_P(KdPacket, DegenerateAndPartialPackets) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  const auto tiles = camera_tiles(Pinhole::looking_at({1.0f, 2.0f, 6.0f}, {0, 0.5f, 0}, {0, 1, 0}, 50.0f, 64), 64, 64);
  Coverage cov;
  for (std::size_t t = 0; t < tiles.size(); t += 5) {
    check_packet(kd, oracle, std::vector<Ray>(64, tiles[t][27]), cov);
    if (HasFatalFailure()) return;
  }
  for (int count : {1, 2, 3, 5, 8, 15, 16, 17, 31, 33, 47, 63}) {
    for (std::size_t t = 0; t < tiles.size(); t += 9) {
      check_packet(kd, oracle, std::vector<Ray>(tiles[t].begin(), tiles[t].begin() + count), cov);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(cov.hits, 0u);
}

// Incoherent packets: the single-ray tests' ray kinds (random, axis-parallel, in and from
// split planes, finite segments, origins inside), 64 random rays per packet, so lanes
// differ in direction octant and shear permutation.
TEST_P(KdPacket, IncoherentPackets) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  const std::vector<SplitPlane> planes = split_planes(kd);
  TestRng rng(isa_seed() + 11);
  Coverage cov;
  for (RayKind kind : {RayKind::Random, RayKind::Aimed, RayKind::Inside, RayKind::AxisParallel,
                       RayKind::InSplitPlane, RayKind::FromSplitPlane, RayKind::Segment}) {
    for (int p = 0; p < 6; ++p) {
      std::vector<Ray> rays;
      for (int i = 0; i < 64; ++i) rays.push_back(make_ray(kind, tris, tris.bounds(), planes, rng));
      check_packet(kd, oracle, rays, cov);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(cov.hits, 0u);
  EXPECT_GT(cov.mixed_sign_packets, 0u);
}

// Mixed packets: half camera rays, half from other kinds, interleaved.
TEST_P(KdPacket, MixedCoherentAndIncoherentLanes) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  const std::vector<SplitPlane> planes = split_planes(kd);
  const auto tiles = camera_tiles(Pinhole::looking_at({0.5f, 1.5f, 5.0f}, {0, 0.5f, 0}, {0, 1, 0}, 60.0f, 64), 64, 64);
  TestRng rng(isa_seed() + 13);
  Coverage cov;
  for (std::size_t t = 0; t < tiles.size(); t += 3) {
    std::vector<Ray> rays = tiles[t];
    for (std::size_t i = 1; i < rays.size(); i += 2) {
      rays[i] = make_ray(i % 4 == 1 ? RayKind::AxisParallel : RayKind::Random, tris, tris.bounds(), planes, rng);
    }
    check_packet(kd, oracle, rays, cov);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(cov.mixed_sign_packets, 0u);
}

// Lanes the packet kernel hands to the single-ray paths: scenes at scales where some rays
// need the double or scan plans, and packets with NaN, infinite, zero-length and empty
// rays among camera rays.
TEST_P(KdPacket, ScaledScenesAndBadLanes) {
  Coverage cov;
  std::size_t plans[4] = {0, 0, 0, 0};  // miss, scan, traverse in double, traverse in float
  for (float scale : {1e-9f, 1e-4f, 1.0f, 1e5f, 1e12f}) {
    TriangleSoA tris = spheres_and_boxes();
    for (int k = 0; k < 3; ++k)
      for (std::size_t i = 0; i < tris.size(); ++i) {
        tris.x[k][i] *= scale;
        tris.y[k][i] *= scale;
        tris.z[k][i] *= scale;
      }
    const KdTree kd(tris, {}, isa());
    const BruteForce oracle(tris);
    const Pinhole cam = Pinhole::looking_at(glm::vec3(1.0f, 2.0f, 6.0f) * scale, glm::vec3(0.0f, 0.5f, 0.0f) * scale,
                                            {0, 1, 0}, 50.0f, 32);
    auto tiles = camera_tiles(cam, 32, 32);
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      std::vector<Ray>& rays = tiles[t];
      if (t % 3 == 0) {  // unit-length directions far below the scene's scale
        for (Ray& r : rays) r.dir *= 1e-30f;
      }
      if (t % 4 == 1) {
        const float nan = std::nanf("");
        rays[3].org.x = nan;
        rays[9].dir = glm::vec3(0.0f);
        rays[17].dir.y = kInfinity;
        rays[40].tnear = 5.0f, rays[40].tfar = 1.0f;
        rays[41].tfar = nan;
      }
      for (const Ray& r : rays) {
        const KdRaySetup setup = kd_setup_ray(view(kd), r);
        ++plans[setup.plan == KdPlan::Miss ? 0 : setup.plan == KdPlan::Scan ? 1 : setup.float_ok ? 3 : 2];
      }
      check_packet(kd, oracle, rays, cov);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(cov.hits, cov.rays / 10);
  EXPECT_GT(plans[0], 0u) << "no lane took the miss plan";
  EXPECT_GT(plans[1], 0u) << "no lane took the scan plan";
  EXPECT_GT(plans[2], 0u) << "no lane took the double-precision plan";
  EXPECT_GT(plans[3], 0u) << "no lane took the packet (float) plan";
}

// Lanes on both sides of the vector setup's limits (kd_packet_setup-inl.h): a direction
// component around 2^-60, whole directions scaled so E^2 max(E, D) / max|dir| crosses
// 2^-50 and 2^90, and odd ray ranges (infinite or huge tnear, tfar below tnear, zero,
// negative or inside the scene), mixed with ordinary camera lanes in each packet.
TEST_P(KdPacket, LanesAcrossTheVectorSetupLimits) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  auto tiles = camera_tiles(Pinhole::looking_at({1.0f, 2.0f, 6.0f}, {0, 0.5f, 0}, {0, 1, 0}, 50.0f, 32), 32, 32);
  Coverage cov;
  int variant = 0;
  for (std::vector<Ray>& rays : tiles) {
    for (std::size_t i = 0; i < rays.size(); i += 3, ++variant) {
      Ray& r = rays[i];
      switch (variant % 12) {
        case 0: r.dir.x = std::ldexp(1.0f, -58 - variant % 5); break;  // 2^-58 .. 2^-62
        case 1: r.dir.y = -std::ldexp(1.0f, -61 + variant % 3); break;
        case 2: r.dir *= std::ldexp(1.0f, 45 + variant % 20); break;    // magnitude around 2^-50
        case 3: r.dir *= std::ldexp(1.0f, -95 + variant % 15); break;   // around 2^90
        case 4: r.tnear = -kInfinity; break;
        case 5: r.tnear = -1e30f; r.tfar = 1e30f; break;
        case 6: r.tfar = -kInfinity; break;
        case 7: r.tfar = 0.0f; break;
        case 8: r.tnear = r.tfar = 5.0f; break;
        case 9: r.tnear = 3e38f; break;
        case 10: r.tfar = 5.5f + 0.01f * float(variant % 50); break;  // ends near the spheres
        default: r.tnear = 5.0f + 0.02f * float(variant % 40); break;  // starts inside the scene
      }
    }
    check_packet(kd, oracle, rays, cov);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(cov.hits, cov.rays / 10);
  EXPECT_GT(cov.partial_packets, 0u);
}

// More than 64 rays are split into packets; a count of 0 does nothing; negative throws.
// The same for occlusion packets.
TEST_P(KdPacket, CountsBeyondOnePacket) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const auto tiles = camera_tiles(Pinhole::looking_at({1.0f, 2.0f, 6.0f}, {0, 0.5f, 0}, {0, 1, 0}, 50.0f, 64), 64, 64);
  std::vector<Ray> rays;
  for (int t = 20; t < 23; ++t) rays.insert(rays.end(), tiles[t].begin(), tiles[t].end());
  rays.resize(150);
  std::vector<Hit> hits(rays.size());
  kd.intersect_packet(rays.data(), hits.data(), static_cast<int>(rays.size()));
  std::size_t valid = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(same_hit(hits[i], kd.intersect(rays[i]))) << "ray " << i;
    valid += hits[i].valid() ? 1 : 0;
  }
  EXPECT_GT(valid, 0u);
  Hit untouched{1.0f, 7u, 0.25f, 0.5f};
  kd.intersect_packet(rays.data(), &untouched, 0);
  EXPECT_EQ(untouched.prim, 7u);
  EXPECT_THROW(kd.intersect_packet(rays.data(), hits.data(), -1), std::invalid_argument);

  const std::unique_ptr<bool[]> blocked(new bool[rays.size()]);
  kd.occluded_packet(rays.data(), blocked.get(), static_cast<int>(rays.size()));
  std::size_t occluded = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(blocked[i], kd.occluded(rays[i])) << "ray " << i;
    occluded += blocked[i] ? 1 : 0;
  }
  EXPECT_GT(occluded, 0u);
  EXPECT_LT(occluded, rays.size());
  bool unset = true;
  kd.occluded_packet(rays.data(), &unset, 0);
  EXPECT_TRUE(unset);
  EXPECT_THROW(kd.occluded_packet(rays.data(), blocked.get(), -1), std::invalid_argument);
}

// Occlusion packets as the path tracer traces them: shadow segments from points on the
// scene's triangles towards points of a square light above it, ending just short of it,
// 64 at a time from one neighbourhood. Some lanes are blocked, some not, in most packets.
TEST_P(KdPacket, ShadowSegmentPackets) {
  const TriangleSoA tris = spheres_and_boxes();
  const KdTree kd(tris, {}, isa());
  const BruteForce oracle(tris);
  const Bounds3 b = tris.bounds();
  const glm::vec3 e = b.extent();
  TestRng rng(isa_seed() + 17);
  std::size_t blocked = 0, open = 0, partial = 0;
  for (int p = 0; p < 40; ++p) {
    // Neighbouring triangles: a run of indices (procedural meshes are emitted in strips).
    const std::uint32_t first = rng.below(std::uint32_t(tris.size()));
    std::vector<Ray> rays;
    for (int i = 0; i < 64; ++i) {
      const std::uint32_t prim = std::min<std::uint32_t>(first + rng.below(16), std::uint32_t(tris.size()) - 1);
      const TriangleCorners t = triangle_corners(tris, prim);
      double u = rng.uniform(), v = rng.uniform();
      if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
      const glm::vec3 point = glm::vec3(glm::dvec3(t[0]) * (1.0 - u - v) + glm::dvec3(t[1]) * u + glm::dvec3(t[2]) * v);
      const glm::vec3 light(b.lo.x + e.x * float(rng.uniform()), b.hi.y + 0.25f * e.y,
                            b.lo.z + e.z * float(rng.uniform()));
      const glm::vec3 n = glm::normalize(glm::cross(t[1] - t[0], t[2] - t[0]));
      Ray r;
      r.org = SurfaceOffset(point, n, t).origin_towards(light);
      r.dir = light - r.org;
      r.tfar = 1.0f - 1e-4f;
      rays.push_back(r);
    }
    const std::unique_ptr<bool[]> out(new bool[rays.size()]);
    kd.occluded_packet(rays.data(), out.get(), static_cast<int>(rays.size()));
    std::size_t here = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(out[i], oracle.occluded(rays[i])) << "packet " << p << " lane " << i << ", " << describe(rays[i]);
      here += out[i] ? 1 : 0;
    }
    blocked += here, open += rays.size() - here;
    partial += here > 0 && here < rays.size() ? 1 : 0;
  }
  EXPECT_GT(blocked, 0u);
  EXPECT_GT(open, 0u);
  EXPECT_GT(partial, 10u) << "most packets should have blocked and open lanes";
}

INSTANTIATE_TEST_SUITE_P(AllIsas, KdPacket, ::testing::ValuesIn(kd_test_isas()), kd_isa_param_name);

}  // namespace
}  // namespace lancer::test
